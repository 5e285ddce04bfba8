"""The error budget: every share of a tolerance, each with the bound it pays for.

A written file (an SVG, a font) is within a user's ``tol`` of the exact shape
because ``tol`` is split into parts whose errors add by the triangle inequality of
the Hausdorff (and Fréchet) distance:

- the *geometry* (a sum, offset, stroke or morph frame, :func:`morph.minkowski.
  minkowski_sum`) within ``SUM_SHARE * tol`` of the exact shape, itself split into
  the convolution, flattening, grid and contraction shares below;
- the *export* (:mod:`morph.export`: certified cubic fits, for TrueType then cu2qu
  within ``QUADRATIC_CUBIC_SHARE`` / the rest, then rounding of the written
  coordinates, ``ROUND_SHARE``) within the rest.

:func:`plan` is the one function that splits a writer's tolerance; every command
and both font writers call it.  :meth:`Budget.after` gives the export what the
geometry left unspent once its error is bounded (:func:`export_tolerance`).
"""

import math
from collections import namedtuple

__all__ = ["Budget", "plan", "export_tolerance", "SUM_SHARE", "QUADRATIC_CUBIC_SHARE",
           "ROUND_SHARE", "PHI_SHARE", "CONV_SHARE", "FLAT_SHARE", "GRID_SHARE",
           "CONTRACT_SHARE", "FIRST_SHARE", "TIP_MARGIN", "TIP_FLOOR", "TIP_REACH",
           "RETRY_SHARE", "TURN_SHARE", "POLYGON_SHARE"]

# ------------------------------------------------------------ a written file
#: The geometry's share of a writer's tolerance; the export gets the rest.  A
#: quarter: the cubics must follow the geometry's pieces, ripples of the QAC
#: approximation included, and export slack is what lets one cubic span several
#: pieces (fewer points for a slower sum; bench/export.py measures both).
SUM_SHARE = 0.25
#: TrueType export: the certified cubic fit's share of the export tolerance; cu2qu
#: (its own same-parameter check) gets the rest, and the two errors add (Fréchet).
QUADRATIC_CUBIC_SHARE = 0.5
#: SVG export: at most this share of the export tolerance goes to rounding the
#: written coordinates (a control point moves by <= 0.5 * 10^-d * sqrt 2, the curve
#: as far at the same parameter); the cubic fit gets >= 0.95 of it.  One decimal
#: more than a share of 0.2 would need, for fewer points (bench/peers.py).
ROUND_SHARE = 0.05
#: Cubic certificate: the reparametrisation phi must follow the closest-point feet
#: within this share of the fit's tolerance (else a higher degree or a Möbius factor
#: is tried, :mod:`morph.export`).
PHI_SHARE = 0.2

# ------------------------------------------------------------ a sum (minkowski_sum)
# Shares of the sum's tol; they add up to 1.  A gap narrower than twice the
# convolution share may close (the pieces on its sides may overlap), a feature
# thinner than twice the flattening and grid shares may merge (morph.trim): the
# split makes both about 1 tol.  The convolution costs little (QAC pieces grow as
# e^-1/4 or slower), the flattening most of the trimming (points grow as e^-1/2),
# hence the larger convolution share (bench/adaptive.py measures it).
#: Convolution pieces within this share of the exact convolution curve (QAC's
#: a-priori bound, :func:`morph.qac.qac_error_bound`).
CONV_SHARE = 0.5
#: Polylines on which the topology is decided, within this share of the pieces.
FLAT_SHARE = 0.35
#: Grid of the integer polygon engine: spacing GRID_SHARE * sqrt(2) * tol.
GRID_SHARE = 0.1
#: Runs shorter than this share are contracted to a point.
CONTRACT_SHARE = 0.05
#: The first round approximates the pairs that may meet another at a corner
#: (:func:`morph.convolve.crossing_rows`) within this share of the convolution
#: share, so that corners turning by up to 2 acos(FIRST_SHARE / TIP_MARGIN) (about
#: 127 degrees) need no second round, which trims the whole sum again and costs more
#: than the extra pieces (bench/stroke_sum.py); pairs that meet no other keep the
#: whole convolution share (bench/scaling.py).
FIRST_SHARE = 0.4
#: Sharp corners (wedge tips): two curves each within e meet up to e / cos(phi / 2)
#: from the exact corner turning by phi, so a piece through such a corner gets
#: ``CONV_SHARE * tol * TIP_MARGIN * max(cos(phi / 2), TIP_FLOOR)``: TIP_MARGIN for
#: phi measured on approximations, TIP_FLOOR the smallest cos(phi / 2) honoured.
TIP_MARGIN = 0.9
TIP_FLOOR = 1e-3
#: A piece's box within this many tol of a corner counts as passing through it.
TIP_REACH = 0.5

# ------------------------------------------------------------ font fallbacks
#: A brushed glyph whose sum raised is computed again at this share of its
#: geometry tolerance (other crossings and flattenings, same bound).
RETRY_SHARE = 0.25
#: ... then with the nib turned by an angle moving it at most this share of the
#: geometry tolerance, the sum getting the rest: the outline stays within it.
TURN_SHARE = 0.5
#: Polygon fallback: each operand flattened within this share of the glyph's
#: tolerance; the Clipper sum of the polygons is exact, so the two add to tol.
POLYGON_SHARE = 0.5


class Budget(namedtuple("Budget", "geometry export cubic cu2qu total")):
    """A writer's tolerance split by :func:`plan`: ``geometry + export == total``;
    the export is ``cubic`` (certified fit) + ``cu2qu`` (TrueType, else 0).
    ``geometry, export = plan(tol)[:2]`` unpacks the two shares."""

    __slots__ = ()

    def after(self, geometry_bound):
        """The export's tolerance once the geometry's error is bounded by
        ``geometry_bound`` (<= ``geometry``): :func:`export_tolerance`."""
        return export_tolerance(self.total, geometry_bound)


def _check_tol(tol):
    tol = float(tol)
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    return tol


def plan(tol, quadratic=False, share=SUM_SHARE):
    """Split a writer's total ``tol`` into a :class:`Budget`.

    The geometry (a sum computed within ``geometry``, Hausdorff distance) and an
    exporter bounded by ``export`` (Fréchet, hence Hausdorff, distance between the
    written curves and the computed pieces) give a file within ``tol`` of the exact
    shape by the triangle inequality.  With ``quadratic`` (TrueType) the export is
    split again: certified cubics within ``cubic``, cu2qu within ``cu2qu``.

    Raises:
        ValueError: tol not positive and finite, or share not in (0, 1).
    """
    tol = _check_tol(tol)
    if not 0.0 < share < 1.0:
        raise ValueError("share must be in (0, 1), got %r" % (share,))
    geometry = share * tol
    export = tol - geometry
    cubic = QUADRATIC_CUBIC_SHARE * export if quadratic else export
    return Budget(geometry, export, cubic, export - cubic, tol)


def export_tolerance(tol, geometry_bound):
    """The export's share of a total ``tol`` once the geometry's error is bounded.

    ``geometry_bound`` must be a stated upper bound of the Hausdorff distance between
    the computed pieces and the exact shape (never a measurement), e.g. the ``bound``
    of :func:`morph.minkowski.minkowski_sum`'s result: the shares of its tolerance
    spent on anything but the convolution plus the largest a-priori bound e of its
    convolution pieces (0 for exact ones such as a TrueType glyph ⊕ disk), e / cos(phi
    / 2) at a corner turning by phi; never more than its tolerance.  The result is
    ``tol - geometry_bound``: an exporter within it keeps the written file within
    ``tol`` of the exact shape (triangle inequality).

    Raises:
        ValueError: tol not positive and finite, or geometry_bound not in [0, tol).
    """
    tol, bound = _check_tol(tol), float(geometry_bound)
    if not 0.0 <= bound < tol:
        raise ValueError("geometry_bound must be in [0, tol), got %r" % (geometry_bound,))
    return tol - bound

"""Nibs: the convex pens of brushed and stroked shapes (paper Fig. 5), in the
geometry layer, where :func:`morph.stroke.stroke_paths` and the font writers both
find them.

A nib is a region of one convex loop with the pen point at the origin, swept
without rotation.  :func:`ellipse_nib` makes an exact ellipse;
:func:`check_convex_nib` refuses anything else (NibError); :func:`nib_is_symmetric`
tells a centrally symmetric nib (N = -N), for which a half-turned component of a
glyph may stay a component; :func:`region_extent` is a nib's (any region's) box.
"""

import numpy as np

from . import piece as pc
from . import polyline as pl
from .errors import NibError

__all__ = ["ellipse_nib", "check_convex_nib", "convex_region", "nib_is_symmetric",
           "region_extent"]


def ellipse_nib(width, height, angle_deg=0.0):
    """Exact elliptical nib: width x height (font units), rotated by angle (degrees).

    Raises:
        NibError: width or height not positive (``.nib`` = the three arguments).
    """
    if not (width > 0 and height > 0):
        raise NibError("nib width and height must be positive, got %g x %g"
                       % (width, height), (width, height, angle_deg))
    return [pc.ellipse((0.0, 0.0), width / 2.0, height / 2.0, np.radians(angle_deg))]


#: the nibs found convex, by :func:`_nib_key` (oldest first): a command checks its nib
#: where it reads it and each library function it calls checks it again (``morph
#: stroke``: three Gauss maps of the same nib, ~5 ms each); the last few are kept
_CONVEX = {}
_CONVEX_KEPT = 8


def _nib_key(loop):
    """The loop's pieces as bytes with their shapes: equal keys, equal pieces."""
    return tuple((np.shape(p), np.asarray(p, dtype=float).tobytes()) for p in loop)


def check_convex_nib(nib):
    """Check that the nib is a single convex loop (its Gauss map turns monotonically
    through 2 pi).

    Raises:
        NibError: not one loop, or not convex (``.nib`` = the region).
    """
    from .gauss import TURN_EPS, gauss_map, turns_convex

    if len(nib) != 1:
        raise NibError("the nib must be one closed convex shape, got %d loops" % len(nib), nib)
    key = _nib_key(nib[0])
    if key in _CONVEX:
        return
    edges = gauss_map(nib[0])
    if turns_convex(edges):
        _CONVEX[key] = None
        while len(_CONVEX) > _CONVEX_KEPT:
            del _CONVEX[next(iter(_CONVEX))]
        return
    bad = [e for e in edges if e.sweep < -TURN_EPS]
    if bad:
        raise NibError("the nib is not convex: it turns clockwise at %s (only convex "
                       "nibs are supported)" % (np.round(bad[0].point, 3).tolist(),), nib)
    raise NibError("the nib is not convex (total turning %.3f rad)"
                   % sum(e.sweep for e in edges), nib)


def convex_region(nib):
    """:func:`check_convex_nib`, then the nib as a validated
    :class:`morph.region.Region`: one loop whose tangent turns monotonically
    counter-clockwise through 2 pi is simple and convex, so it bounds a region
    (winding 1 inside, 0 outside), and the sums take it without their winding test
    (:func:`morph.operands.check_operand`: a few ms for a nib, per chunk summed).

    Raises:
        NibError: as :func:`check_convex_nib`.
    """
    from .region import Region, validated

    check_convex_nib(nib)
    if isinstance(nib, Region) and nib.validated:
        return nib
    return validated(nib, getattr(nib, "bound", None))


#: the extents of the last few regions :func:`region_extent` measured, by their
#: loops' :func:`_nib_key`: a command asks for its nib's box where it plans the
#: metrics, where it shifts the outlines and where it turns the nib (a few ms each:
#: the extremes are roots of the tangents)
_EXTENTS = {}


def region_extent(loops):
    """Exact bounding box of a region (xmin, ymin, xmax, ymax)."""
    from .region import region_bbox

    key = tuple(_nib_key(loop) for loop in loops)
    if key not in _EXTENTS:
        _EXTENTS[key] = tuple(float(v) for v in region_bbox(loops))
        while len(_EXTENTS) > _CONVEX_KEPT:
            del _EXTENTS[next(iter(_EXTENTS))]
    return _EXTENTS[key]


def nib_is_symmetric(nib_region, rel=1e-7, directions=360):
    """True when the nib is centrally symmetric about the origin (N = -N).

    Checked on the support function h(u) = max_{x in N} x.u: h(u) = h(-u) for
    ``directions`` unit vectors within ``rel`` times the nib's size, on the nib's
    boundary flattened within that tolerance (a sampled check).  An ellipse from
    :func:`ellipse_nib` is symmetric.

    First, without flattening: when the half turn maps every piece onto a piece
    (:func:`_pieces_map_to_pieces`, e.g. the quarters of an ellipse), the nib is
    symmetric within ``rel`` and the sampled check would say so too; a nib whose
    pieces do not pair up that way gets the sampled check.
    """
    x0, y0, x1, y1 = region_extent(nib_region)
    size = max(x1 - x0, y1 - y0)
    eps = rel * size
    if _pieces_map_to_pieces(nib_region, eps):
        return True
    pts = np.concatenate([pl.flatten(p, eps)[0] for loop in nib_region for p in loop])
    ang = np.linspace(0.0, np.pi, directions, endpoint=False)
    u = np.column_stack([np.cos(ang), np.sin(ang)])
    d = pts @ u.T
    return bool(np.all(np.abs(d.max(axis=0) + d.min(axis=0)) <= 4 * eps))


def _pieces_map_to_pieces(nib_region, eps):
    """True when every piece p of the region has a piece q with the same weights
    (relative to its first) whose control points are those of -p within ``eps``:
    then the boundary's half turn lies within ``eps`` of the boundary (a rational
    Bézier curve with positive weights is a convex combination of its control
    points), so N = -N within ``eps``."""
    pieces = [np.asarray(p, float) for loop in nib_region for p in loop]
    if not pieces or any(p.ndim != 2 or p.shape[1] != 3 or (p[:, 2] <= 0).any()
                         for p in pieces):
        return False
    points = [p[:, :2] / p[:, 2:] for p in pieces]
    weights = [p[:, 2] / p[0, 2] for p in pieces]
    for cp, wp in zip(points, weights):
        if not any(len(cq) == len(cp) and np.abs(cq + cp).max() <= eps
                   and np.abs(wq - wp).max() <= 1e-12 * len(wp)
                   for cq, wq in zip(points, weights)):
            return False
    return True

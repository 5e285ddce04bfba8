"""Independent polygon reference for skeleton strokes (paths ⊕ convex nib), in Clipper.

Nothing here calls the project's stroking or trimming code: the skeleton's pieces and
the nib's loop are flattened with ``morph.polyline.flatten`` (tested on its own), then

    P ⊕ N = (P ⊕ ∂N) ∪ (p0 + N)

is built exactly in Clipper's integer arithmetic for every path P (open: a polyline;
closed: a ring, its outline only, not filled) and unioned over the paths.
``pyclipper.MinkowskiSum(nib, path, closed)`` gives P ⊕ ∂N as the union of the
parallelograms edge ⊕ edge; the nib placed at the path's first point p0 covers the rest
(if x ∈ P ⊕ N, the connected set P meets x - N: either P crosses ∂(x - N), so
x ∈ P ⊕ ∂N, or P lies inside x - N, so p0 ∈ x - N).  A zero-length path gives the nib.

The flattening is within ``tol / 2`` for each operand, so the polygon is within
``tol`` (plus 2 Clipper units of rounding) of the exact stroke in Hausdorff distance.
"""

import numpy as np
import pyclipper

from tests.oracles import need

shapely = need("shapely", "the Clipper stroke's polygons")
from shapely.geometry import MultiPolygon, Polygon  # noqa: E402 - after the check above

from morph import piece as mp  # noqa: E402
from morph import polyline as pl  # noqa: E402
from tests.oracles.reference import (_clipper_union, _polygons, default_scale,  # noqa: E402
                                     region_polylines)


def path_polyline(pieces, tol):
    """(m, 2) polyline of a path's pieces (joined end to start) within tol."""
    pts = [pl.flatten(np.asarray(p, float), tol)[0] for p in pieces]
    out = [pts[0]] + [q[1:] for q in pts[1:]]
    return np.concatenate(out)


def stroke_polygon(paths, nib_region, tol, scale=None):
    """Shapely (Multi)Polygon of the union of paths ⊕ nib (see the module docstring).

    ``paths``: list of ``(pieces, closed)``; ``nib_region``: one convex loop of pieces
    (a list holding one loop).  One Clipper unit is tol/100 unless ``scale`` is given.
    """
    scale = default_scale(tol) if scale is None else scale
    nib = region_polylines(nib_region, tol / 2)
    if len(nib) != 1:
        raise ValueError("the nib must be one loop")
    nib_int = [(int(x), int(y)) for x, y in np.round(nib[0] * scale)]
    if pyclipper.Area(nib_int) < 0:
        nib_int = nib_int[::-1]
    parts = []
    for pieces, closed in paths:
        poly = path_polyline(pieces, tol / 2)
        ip = [(int(x), int(y)) for x, y in np.round(poly * scale)]
        if closed and len(ip) > 1 and ip[0] == ip[-1]:
            ip = ip[:-1]
        dedup = [ip[0]] + [q for a, q in zip(ip, ip[1:]) if q != a]
        x0, y0 = dedup[0]
        parts.append([(x + x0, y + y0) for x, y in nib_int])
        if len(dedup) > 1:
            parts.extend(pyclipper.MinkowskiSum(nib_int, dedup, bool(closed) and len(dedup) > 2))
    return _clipper_union(parts, scale)


def polygon_to_region(geom):
    """Region of line pieces (outer loops counter-clockwise, holes clockwise) of a
    shapely polygon: lets the polygon reference stand in for a stroker."""
    loops = []
    for poly in _polygons(geom):
        poly = shapely.geometry.polygon.orient(poly, 1.0)
        for ring in [poly.exterior] + list(poly.interiors):
            pts = np.asarray(ring.coords)[:-1]
            loops.append([mp.line(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))])
    return loops


def polygon_stroker(flat_tol=0.05):
    """A ``stroke_paths``-compatible function built on :func:`stroke_polygon`
    (``tol`` ignored; flattening within ``flat_tol``): for plumbing tests."""
    def stroke(paths, nib_region, tol):
        return polygon_to_region(stroke_polygon(paths, nib_region, flat_tol))
    return stroke


__all__ = ["path_polyline", "stroke_polygon", "polygon_to_region", "polygon_stroker",
           "MultiPolygon", "Polygon"]

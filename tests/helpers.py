"""Small geometry helpers shared by several test files: sizes, polygons and areas from
control points and ``tests.oracles.reference`` evaluation (nothing here is under test)."""

import numpy as np

from morph import piece as pc
from morph import polyline as pl
from tests.oracles import reference as R


def region_size(region):
    """Largest side of the bounding box of a region's control points."""
    pts = np.concatenate([pc.cartesian(p) for loop in region for p in loop])
    return float(np.ptp(pts, axis=0).max())


def loop_polygons(loops, tol):
    """Each loop as one polygon: its pieces evaluated by ``tests.oracles.reference.bezier_eval``
    at the parameters of ``polyline.flatten(p, tol)``, each piece's end point left to the
    next piece."""
    return [np.concatenate([R.bezier_eval(p, pl.flatten(p, tol)[1])[0][:-1] for p in loop])
            for loop in loops]


def shoelace(poly):
    """Signed area of a closed polygon (counter-clockwise positive)."""
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def polygon_region(p):
    """The region of one loop of line pieces through the points ``p`` (closed)."""
    return [[pc.line(p[i], p[(i + 1) % len(p)]) for i in range(len(p))]]


def square_path_data(x0, y0, s):
    """SVG path data of the axis-aligned square with corner (x0, y0) and side s."""
    return "M%r %r L%r %r L%r %r L%r %r Z" % (x0, y0, x0 + s, y0, x0 + s, y0 + s, x0, y0 + s)

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


def pencil_path(angle, scale):
    """Feather's edit-2 pencil as one closed path (a semicircle, then three lines back
    to its start, which it meets tangentially: the path runs on smoothly through
    where it begins), turned by ``angle`` degrees and scaled."""
    c, s = np.cos(np.radians(angle)), np.sin(np.radians(angle))

    def at(x, y):
        return (scale * (c * x - s * y), scale * (s * x + c * y))

    # the semicircle centred (19, 5) from (17, 3) through (21, 3) to (21, 7)
    arcs = pc.ellipse_arc(at(19, 5), scale * np.sqrt(8), scale * np.sqrt(8),
                          np.radians(angle), -0.75 * np.pi, np.pi)
    corners = [(21, 7), (7.5, 20.5), (2, 22), (3.5, 16.5), (17, 3)]
    return arcs + [pc.line(at(*a), at(*b)) for a, b in zip(corners, corners[1:])]


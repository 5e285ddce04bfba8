"""Gauss maps of loops and compatible subdivision (Sec. 3.2, Defs. 3.2-3.4).

A loop is turned into a cyclic list of *edges* (:class:`Edge`), each with a
monotone tangent angle:

- a *curve* edge is a piece whose tangent angle runs monotonically from ``theta`` to
  ``theta + sweep`` (``sweep > 0``: convex, the curve turns left, Def. 3.2;
  ``sweep < 0``: concave; ``sweep == 0``: a straight segment).  Pieces are split at
  inflections (zeros of x'y'' - x''y') and where the hodograph crosses the x or y
  axis, so every sweep lies within one quadrant (|sweep| <= pi/2);
- a *vertex* edge is a corner of zero length whose Gauss map is the arc of tangent
  angles it turns through, ``sweep > 0`` for a convex (left) turn and ``< 0`` for a
  concave one (Def. 3.4).  Tangent-continuous joins (turn below ``angle_tol``) get
  no vertex.

Tangent angles are *lifted* (unwrapped) along the loop, so a counter-clockwise outer
loop turns through +2 pi and a clockwise hole through -2 pi.  Working with tangent
angles is the same as working with normals: the outward normal is the tangent turned
by -90 degrees (Eq. 20).
"""

from dataclasses import dataclass

import numpy as np

from . import bernstein as bz
from . import piece as pc
from .errors import DegenerateCurveError

TWO_PI = 2.0 * np.pi


@dataclass
class Edge:
    """One edge of a loop's Gauss map.

    kind: "curve" or "vertex".  piece: the (n+1, 3) control points of a curve edge
    (None for a vertex).  point: the vertex position (for a curve, its start point).
    theta: lifted tangent angle at the start.  sweep: signed angle turned along the
    edge.  The edge covers the angle interval between theta and theta + sweep.
    """

    kind: str
    piece: object
    point: np.ndarray
    theta: float
    sweep: float

    @property
    def lo(self):
        return min(self.theta, self.theta + self.sweep)

    @property
    def hi(self):
        return max(self.theta, self.theta + self.sweep)

    @property
    def sign(self):
        """+1 convex, -1 concave, 0 straight (curve) or no turn."""
        return int(np.sign(self.sweep))


def _split_at(piece, params):
    """Split a piece at sorted interior parameters."""
    out = []
    rest = piece
    t_prev = 0.0
    for t in params:
        u = (t - t_prev) / (1.0 - t_prev)
        left, rest = pc.split(rest, u)
        out.append(left)
        t_prev = t
    out.append(rest)
    return out


def _interior(ts, eps=1e-9):
    ts = np.asarray(ts, float)
    return np.unique(ts[(ts > eps) & (ts < 1.0 - eps)])


def inflection_params(piece):
    """Interior parameters where x'y'' - x''y' changes sign (Def. 3.2)."""
    k = pc.curvature_numerator(piece)
    if np.max(np.abs(k)) == 0.0:
        return np.empty(0)
    roots = _interior(bz.roots(k))
    # keep only sign changes (a double root is a flat point, not an inflection)
    keep = []
    for r in roots:
        a, b = bz.evaluate(k, [max(r - 1e-6, 0.0), min(r + 1e-6, 1.0)])
        if a * b < 0:
            keep.append(r)
    return np.array(keep)


def axis_params(piece):
    """Interior parameters where the hodograph crosses the x or y axis (Sec. 3.2)."""
    h = pc.tangent_numerator(piece)
    ts = np.concatenate([bz.roots(h[:, 0]), bz.roots(h[:, 1])])
    return _interior(ts)


def split_monotone(piece):
    """Split a piece so that each part has monotone tangent angle within one quadrant.

    Splits at inflections and hodograph axis crossings.  Raises DegenerateCurveError
    for an interior cusp (the hodograph vanishes inside the piece).
    """
    ts = _interior(np.concatenate([inflection_params(piece), axis_params(piece)]))
    parts = _split_at(piece, ts) if ts.size else [piece]
    out = []
    for part in parts:
        size = max(np.ptp(pc.cartesian(part), axis=0).max(), 1e-300)
        if size < 1e-12 * max(1.0, np.abs(pc.cartesian(part)).max()):
            continue  # zero-length sliver from splitting at coincident roots
        _check_no_cusp(part)
        out.append(part)
    return out


def _check_no_cusp(piece):
    h = pc.tangent_numerator(piece)
    t = np.linspace(0.0, 1.0, 33)[1:-1]
    v = bz.evaluate(h, t)
    scale = np.abs(h).max()
    if scale == 0.0:
        raise DegenerateCurveError("zero-length curve piece", piece)
    if np.any(np.hypot(v[:, 0], v[:, 1]) < 1e-10 * scale):
        raise DegenerateCurveError("curve piece has a cusp (zero tangent) inside", piece)


def _wrap(a):
    """Angle wrapped into (-pi, pi]."""
    return a - TWO_PI * np.ceil((a - np.pi) / TWO_PI)


def gauss_map(loop, angle_tol=1e-10):
    """Edges (curves and corner vertices) of a closed loop with lifted tangent angles.

    Def. 3.4: a corner turning left (convex) has sweep > 0, right (concave) < 0.
    Raises DegenerateCurveError where the loop reverses direction (a turn of pi).
    """
    curves = [part for p in loop for part in split_monotone(np.asarray(p, float))]
    if not curves:
        raise DegenerateCurveError("loop has no curve of nonzero length", None)
    ends = []
    for c in curves:
        t0, t1 = pc.end_tangents(c)
        a0 = np.arctan2(t0[1], t0[0])
        sweep = _wrap(np.arctan2(t1[1], t1[0]) - a0)
        if abs(sweep) < angle_tol:
            sweep = 0.0
        ends.append((a0, sweep))
    edges = []
    theta = ends[0][0]
    n = len(curves)
    for i, c in enumerate(curves):
        a0, sweep = ends[i]
        if i > 0:
            theta = theta + _wrap(a0 - theta)  # keep lifted angle continuous
        edges.append(Edge("curve", c, pc.start(c), theta, sweep))
        theta = theta + sweep
        nxt_a0 = ends[(i + 1) % n][0]
        turn = _wrap(nxt_a0 - theta)
        if abs(turn) > np.pi - 1e-9:
            raise DegenerateCurveError(
                "loop reverses direction (a cusp or spike) at %s" % (pc.end(c),), c)
        if abs(turn) >= angle_tol:
            edges.append(Edge("vertex", None, pc.end(c), theta, turn))
            theta = theta + turn
    return edges


def total_turning(edges):
    """Sum of sweeps: +2 pi for a counter-clockwise simple loop, -2 pi for a hole."""
    return float(sum(e.sweep for e in edges))


def angle_param(piece, theta):
    """Parameter t where the tangent angle of a monotone piece equals theta.

    Solves cross(H(t), d) = 0 with d = (cos theta, sin theta) for the hodograph
    direction H (Eq. 27 specialised to one curve) and keeps the root where H points
    along d.  The piece must come from :func:`split_monotone` (|sweep| <= pi/2).
    """
    h = pc.tangent_numerator(piece)
    d = np.array([np.cos(theta), np.sin(theta)])
    f = h[:, 1] * d[0] - h[:, 0] * d[1]
    ends = bz.evaluate(f, [0.0, 1.0])
    scale = np.abs(f).max()
    if scale == 0.0:
        return 0.0
    if abs(ends[0]) <= 1e-14 * scale:
        return 0.0
    if abs(ends[1]) <= 1e-14 * scale:
        return 1.0
    roots = bz.roots(f)
    if roots.size == 0:
        # theta at (numerically) an end: take the closer end
        return 0.0 if abs(ends[0]) < abs(ends[1]) else 1.0
    hv = bz.evaluate(h, roots)
    good = roots[hv @ d > 0]
    if good.size == 0:
        return float(roots[0])
    return float(good[0])


def restrict(edge, lo, hi):
    """The part of an edge whose tangent angles lie in [lo, hi] (lifted, same branch).

    Returns (piece_or_None, point, theta_start, sweep) for the restricted edge, in
    the edge's own direction of travel.
    """
    if edge.kind == "vertex" or edge.sweep == 0.0:
        th = edge.theta if edge.sweep == 0.0 else (lo if edge.sweep > 0 else hi)
        sweep = 0.0 if edge.sweep == 0.0 else (hi - lo) * edge.sign
        return edge.piece, edge.point, th, sweep
    if edge.sweep > 0:
        a, b = lo, hi
    else:
        a, b = hi, lo
    t0 = 0.0 if abs(a - edge.theta) < 1e-13 else angle_param(edge.piece, a)
    end_theta = edge.theta + edge.sweep
    t1 = 1.0 if abs(b - end_theta) < 1e-13 else angle_param(edge.piece, b)
    sub = pc.subsegment(edge.piece, t0, t1) if (t0 > 0.0 or t1 < 1.0) else edge.piece
    return sub, pc.start(sub), a, b - a


def point_at_angle(edge, theta):
    """The point of an edge whose tangent angle is theta (vertex: its position)."""
    if edge.kind == "vertex":
        return edge.point
    if edge.sweep == 0.0:
        return edge.point
    return pc.evaluate(edge.piece, angle_param(edge.piece, theta))[0]

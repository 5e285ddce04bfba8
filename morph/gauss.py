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

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import math
from dataclasses import dataclass
from itertools import chain

import numpy as np

from . import bernstein as bz
from . import piece as pc
from . import moments as mo
from . import polyline as pl
from .errors import DegenerateCurveError
from .polyline import winding_number

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


def _split_params_many(pieces, inflections=True, axes=True, eps=1e-9):
    """Sorted interior split parameters of each piece: inflections (roots of
    x'y'' - x''y' where it changes sign; a double root is a flat point, not an
    inflection) and hodograph axis crossings (roots of each component of the
    tangent numerator).  Pieces of one degree and kind (polynomial or rational) are
    handled together: one batched root finder call per polynomial family
    (:func:`morph.bernstein.roots_many`)."""
    out = [np.empty(0)] * len(pieces)
    o, r = _split_params_arrays(pieces, inflections, axes, eps)
    bounds = np.searchsorted(o, np.arange(len(pieces) + 1))
    for k in np.flatnonzero(np.diff(bounds)).tolist():
        out[k] = r[bounds[k]:bounds[k + 1]]
    return out


def _split_params_arrays(pieces, inflections=True, axes=True, eps=1e-9):
    """The split parameters of :func:`_split_params_many` as two arrays (piece,
    parameter), sorted by piece, then parameter.  The polynomials of every kind
    group (:func:`_root_rows`) are solved in one :func:`morph.bernstein.roots_many`
    call per number of coefficients (each row's roots are its own: the same
    numbers as a call per group and family)."""
    own, par = [np.zeros(0, np.int64)], [np.zeros(0)]
    for c, piece, curving in _root_rows(pieces, inflections, axes):
        o, r = bz.roots_many(c)
        inside = (r > eps) & (r < 1.0 - eps)
        o, r = o[inside], r[inside]
        keep = ~curving[o]
        test = (~keep).nonzero()[0]
        if len(test):    # a root of x'y'' - x''y' splits where the sign changes
            ot, rt = o[test], r[test]
            a = bz.evaluate_many(c[ot], np.maximum(rt - 1e-6, 0.0))
            b = bz.evaluate_many(c[ot], np.minimum(rt + 1e-6, 1.0))
            keep[test] = a * b < 0
        own.append(piece[o[keep]])
        par.append(r[keep])
    o, r = np.concatenate(own), np.concatenate(par)
    order = np.lexsort((r, o))
    o, r = o[order], r[order]
    keep = np.ones(len(r), bool)
    keep[1:] = (o[1:] != o[:-1]) | (r[1:] != r[:-1])
    return o[keep], r[keep]


def _root_rows(pieces, inflections, axes):
    """[(polynomials (m, w), the piece of each row, whether each row is a curvature
    numerator)] of :func:`_split_params_arrays`, one item per number of
    coefficients w: of each kind group (:func:`morph.piece.kind_groups`) the
    curvature numerators (``inflections``) and both components of the tangent
    numerators (``axes``)."""
    rows = []
    for ks, stack, rational in pc.kind_groups(pieces):
        h = pc.tangent_numerator_many(stack, rational)
        ks = np.asarray(ks, np.int64)
        if inflections:
            rows.append((pc.curvature_numerator_many(h), ks, True))
        if axes:
            rows += [(h[:, :, 0], ks, False), (h[:, :, 1], ks, False)]
    out = []
    widths = [c.shape[1] for c, _, _ in rows]
    for w in dict.fromkeys(widths):
        mine = [rows[k] for k in range(len(rows)) if widths[k] == w]
        flags = np.concatenate([np.full(len(ks), f) for _, ks, f in mine])
        out.append((np.concatenate([c for c, _, _ in mine]),
                    np.concatenate([ks for _, ks, _ in mine]), flags))
    return out


def _monotone_parts(pieces, check=True):
    """:func:`split_monotone_many` of a :class:`morph.piece.Pieces` as arrays: (the
    kept parts of every piece, in order, as a Pieces; the piece of each part).  The
    cut pieces are split in rounds, the j-th cut of every one at once."""
    o, r = _split_params_arrays(pieces)
    if not len(o):
        parts, owner = pieces, np.arange(len(pieces))
    else:
        cut = pl.unique(o)
        bounds = np.searchsorted(o, np.append(cut, cut[-1] + 1))
        n_cuts = np.diff(bounds)
        n_parts = np.ones(len(pieces), np.int64)
        n_parts[cut] = n_cuts + 1
        owner = np.repeat(np.arange(len(pieces)), n_parts)
        first = np.cumsum(n_parts) - n_parts
        whole = np.ones(len(pieces), bool)
        whole[cut] = False
        groups = []
        for ks, h in pieces.groups:
            w = whole[ks]
            if w.any():
                groups.append((first[ks[w]], h.compress(w, axis=0)))
        # the cut pieces split at their parameters in rounds, the j-th cut of every
        # piece with one at once (:func:`morph.piece.split_at`'s steps, the same
        # float operations)
        for sel, h in pieces.take(cut).groups:
            m = n_cuts[sel]
            ts = r[bounds[sel][:, None] + np.minimum(np.arange(m.max()), m[:, None] - 1)]
            rest, prev = h.copy(), np.zeros(len(sel))
            for j in range(int(m.max())):
                on = np.flatnonzero(m > j)
                t = ts[on, j]
                left, rest[on] = bz.split_many(rest.take(on, axis=0),
                                               (t - prev[on]) / (1.0 - prev[on]))
                prev[on] = t
                groups.append((first[cut[sel[on]]] + j, left))
            groups.append((first[cut[sel]] + m, rest))
        parts = _merged(groups, int(n_parts.sum()))
    keep = _kept_many(parts, check)
    if keep.all():
        return parts, owner
    idx = np.flatnonzero(keep)
    return _taken(parts, idx), owner[idx]


def _merged(groups, n):
    """A :class:`morph.piece.Pieces` of (indices, stack) parts, those of one degree
    joined, each stack's rows in ascending order, the stacks in the order of their
    first piece (as a list's stacks are)."""
    by = {}
    for ks, h in groups:
        by.setdefault(h.shape[1], []).append((ks, h))
    out = []
    for lst in by.values():
        ks = np.concatenate([k for k, _ in lst])
        h = np.concatenate([x for _, x in lst]) if len(lst) > 1 else lst[0][1]
        order = np.argsort(ks, kind="stable")
        out.append((ks[order], h.take(order, axis=0)))
    out.sort(key=lambda g: g[0][0])
    return pc.Pieces(out, n)


def split_monotone(piece):
    """Split a piece so that each part has monotone tangent angle within one quadrant.

    Splits at inflections and hodograph axis crossings.  Raises DegenerateCurveError
    for an interior cusp (the hodograph vanishes inside the piece).
    """
    piece = np.asarray(piece, float)
    if not _may_split(piece):
        return _keep_parts([piece])
    return split_monotone_many([piece])[0]


def _may_split(piece, eps=1e-13):
    """False when no split parameter can exist: neither component of the tangent
    numerator H nor cross(H, H') changes sign among its Bernstein coefficients
    (ends within eps of zero skipped, as :func:`morph.bernstein.roots_many` does),
    so neither has a root inside (Descartes' rule in the Bernstein basis)."""
    h = pc.tangent_numerator(piece)
    if len(h) == 1:
        return False
    dh = bz.derivative(h)
    k = bz.multiply(h[:, :1], dh[:, 1:2])[:, 0] - bz.multiply(h[:, 1:2], dh[:, :1])[:, 0]
    for c in (h[:, 0], h[:, 1], k):
        scale = np.abs(c).max()
        if scale == 0.0:
            continue
        c = c / scale
        c = c[int(abs(c[0]) <= eps):len(c) - int(abs(c[-1]) <= eps)]
        s = np.sign(c[c != 0])
        if np.any(s[1:] != s[:-1]):
            return True
    return False


def _keep_parts(parts, check=True):
    """The parts of a split piece without zero-length slivers, each checked for
    interior cusps (DegenerateCurveError) if ``check``."""
    kept = []
    for part in parts:
        size = max(np.ptp(pc.cartesian(part), axis=0).max(), 1e-300)
        if size < 1e-12 * max(1.0, np.abs(pc.cartesian(part)).max()):
            continue  # zero-length sliver from splitting at coincident roots
        if check:
            _check_no_cusp(part)
        kept.append(part)
    return kept


def split_monotone_many(pieces, check=True):
    """:func:`split_monotone` of many pieces: the split parameters of all pieces of
    one degree are found together (:func:`_split_params_many`), and the parts are
    checked together (:func:`_kept_many`).  Returns one list of parts per piece.
    ``check=False`` skips the cusp check."""
    pieces = [np.asarray(p, float) for p in pieces]
    parts = [pc.split_at(piece, ts) if ts.size else [piece]
             for piece, ts in zip(pieces, _split_params_many(pieces))]
    flat = [q for ps in parts for q in ps]
    keep = _kept_many(flat, check)
    out, k = [], 0
    for ps in parts:
        out.append([q for q, ok in zip(ps, keep[k:k + len(ps)]) if ok])
        k += len(ps)
    return out


CUSP_SAMPLES = np.linspace(0.0, 1.0, 33)[1:-1]


def _kept_many(parts, check=True):
    """Which parts to keep: not zero-length slivers (from splitting at coincident
    roots).  With ``check``, a kept part whose hodograph nearly vanishes inside
    (below 1e-10 of its largest coefficient at 31 interior points) raises
    DegenerateCurveError: an interior cusp.  Parts of one degree and kind at once
    (:func:`_keep_parts` is the same test one part at a time)."""
    keep = np.zeros(len(parts), bool)
    for ks, h, rational in pc.kind_groups(parts):
        x = h[..., :2] / h[..., 2:]
        lo, hi = pc.column_extremes(x)
        size = np.maximum(hi[:, 0] - lo[:, 0], hi[:, 1] - lo[:, 1])
        biggest = np.maximum(-lo, hi).max(axis=1)           # the largest |coordinate|
        ok = ~(size < 1e-12 * np.maximum(1.0, biggest))
        keep[ks] = ok
        if not check or not ok.any():
            continue
        tn = pc.tangent_numerator_many(h.compress(ok, axis=0), rational)
        scale = np.abs(tn).max(axis=(1, 2))
        if tn.shape[1] == 1:    # a constant (a line's): its value at every sample
            least = np.hypot(tn[:, 0, 0], tn[:, 0, 1])
        else:
            v = np.einsum("sj,kjd->ksd", bz.basis(tn.shape[1] - 1, CUSP_SAMPLES), tn)
            least = np.hypot(v[..., 0], v[..., 1]).min(axis=1)
        bad = (scale == 0.0) | (least < 1e-10 * scale)
        if bad.any():
            part = h[ok][np.argmax(bad)]
            _check_no_cusp(part)  # the one-part test names the defect
            raise DegenerateCurveError("curve piece has a cusp (zero tangent) inside", part)
    return keep


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


#: Slack of :func:`turns_convex`: a clockwise turn this small counts as none, and
#: the total may miss 2 pi by TURN_TOTAL_EPS (rounding of the edges' angles).
TURN_EPS, TURN_TOTAL_EPS = 1e-9, 1e-6


def turns_convex(edges):
    """Whether a loop's Gauss map (its edges) turns monotonically counter-clockwise
    through exactly 2 pi: the loop is convex, with the outer orientation."""
    sweep = np.array([e.sweep for e in edges], float)
    return bool(np.all(sweep >= -TURN_EPS) and abs(sweep.sum() - TWO_PI) <= TURN_TOTAL_EPS)


def gauss_map(loop, angle_tol=1e-10):
    """Edges (curves and corner vertices) of a closed loop with lifted tangent angles.

    Def. 3.4: a corner turning left (convex) has sweep > 0, right (concave) < 0.
    A turn of pi (a cusp: a spike, a slit, a crescent's tip, the end of an open
    path traced forward and back) is a corner of sweep +pi or -pi: +pi where the
    loop comes back on the left of its way in (a spike or tip of the filled
    side), -pi on the right (a slit).  Where the two ways coincide (a zero-width
    spike or slit, an open path's end) the signs are chosen so that the loop turns
    through 2 pi times the sign of its area (+2 pi for a zero-area loop: a path
    traced forward and back is swept as a filled stroke).  Raises
    DegenerateCurveError if no choice of signs gives that total.
    """
    return gauss_maps([loop], angle_tol)[0]


def gauss_maps(loops, angle_tol=1e-10):
    """:func:`gauss_map` of each loop, all loops at once (:func:`gauss_table`), as
    lists of :class:`Edge`."""
    return gauss_table(loops, angle_tol).maps()


class GaussTable:
    """The Gauss maps of several loops as arrays, one row per edge, the loops' edges
    one after another, each loop's in its order (what :func:`gauss_maps` lists as
    :class:`Edge` objects).

    ``loop``, ``index``: each edge's loop and its position there; ``curve``: curve
    edges (the others are vertices); ``theta``, ``sweep``: lifted start angle and
    signed sweep; ``point``: a curve's start point, a vertex's position;
    ``piece_of``: a curve edge's row in ``curves`` (-1 for a vertex); ``curves``: the
    monotone pieces (a :class:`morph.piece.Pieces`, in edge order); ``n_loops``."""

    def __init__(self, loop, index, curve, theta, sweep, point, piece_of, curves, n_loops):
        self.loop, self.index, self.curve = loop, index, curve
        self.theta, self.sweep, self.point = theta, sweep, point
        self.piece_of, self.curves, self.n_loops = piece_of, curves, n_loops

    def __len__(self):
        return len(self.loop)

    def maps(self):
        """The :class:`Edge` lists of the loops."""
        rows = self.curves.rows()
        out = [[] for _ in range(self.n_loops)]
        theta, sweep = self.theta.tolist(), self.sweep.tolist()
        for e, (lp, c, k) in enumerate(zip(self.loop.tolist(), self.curve.tolist(),
                                           self.piece_of.tolist())):
            out[lp].append(Edge("curve", rows[k], self.point[e], theta[e], sweep[e]) if c
                           else Edge("vertex", None, self.point[e], theta[e], sweep[e]))
        return out

    def split(self, n):
        """(the table of loops [0, n), the table of the others), renumbered."""
        e = int(np.searchsorted(self.loop, n))
        c = int(self.curve[:e].sum())
        parts = []
        for es, cs, lo in ((slice(0, e), np.arange(0, c), 0),
                           (slice(e, None), np.arange(c, len(self.curves)), n)):
            piece_of = self.piece_of[es]
            parts.append(GaussTable(self.loop[es] - lo, self.index[es], self.curve[es],
                                    self.theta[es], self.sweep[es], self.point[es],
                                    np.where(piece_of >= 0, piece_of - cs[:1].sum(), -1),
                                    _taken(self.curves, cs),
                                    (n if lo == 0 else self.n_loops - n)))
        return parts

    def turnings(self):
        """Each loop's total turning (:func:`total_turning`: the sweeps summed in
        order)."""
        sweep = self.sweep.tolist()
        bounds = np.searchsorted(self.loop, np.arange(self.n_loops + 1)).tolist()
        return [float(sum(sweep[a:b])) for a, b in zip(bounds[:-1], bounds[1:])]


def _taken(pieces, idx):
    """``pieces.take(idx)`` with the stacks in the order of their first piece (as a
    list's stacks are)."""
    t = pieces.take(idx)
    return pc.Pieces(sorted(t.groups, key=lambda g: g[0][0]), len(t))


def gauss_table(loops, angle_tol=1e-10, pieces=None, traced=0):
    """:func:`gauss_map` of each loop, all loops at once, as a :class:`GaussTable`:
    the pieces split, their end tangents and points found, the turns at the joins
    and the sides of the cusps resolved in array calls over every loop
    (:func:`_corner_turns_many`); only the lifting of the angles along each loop
    (a running sum, the same float operations as one loop at a time) visits the
    edges one by one.  ``pieces``: the loops' pieces in order, stacked (a
    :class:`morph.piece.Pieces`; None: stacked here).  ``traced``: the first
    ``traced`` loops are paths traced out and back (:func:`morph.stroke.path_loop`),
    whose open cusps are known (:func:`_corner_turns_many`)."""
    sizes = np.fromiter(map(len, loops), np.int64, len(loops))
    if not sizes.sum():
        if loops:
            raise DegenerateCurveError("loop has no curve of nonzero length", None)
        z = np.zeros(0)
        return GaussTable(z.astype(int), z.astype(int), z.astype(bool), z, z,
                          np.zeros((0, 2)), z.astype(int), pc.Pieces([], 0), 0)
    if pieces is None:
        pieces = pc.Pieces.of(list(chain.from_iterable(loops)))
    curves, owner = _monotone_parts(pieces)
    counts = np.bincount(np.repeat(np.arange(len(loops)), sizes)[owner],
                         minlength=len(loops))
    if (counts == 0).any():
        raise DegenerateCurveError("loop has no curve of nonzero length", None)
    first, last = pc.end_tangents_many(curves)
    a0 = np.arctan2(first[:, 1], first[:, 0])
    sweep = _wrap(np.arctan2(last[:, 1], last[:, 0]) - a0)
    sweep = np.where(np.abs(sweep) < angle_tol, 0.0, sweep)
    turns = _corner_turns_many(curves, counts, a0, sweep, last, traced)
    starts, ends = pc.end_points(curves)
    vertex = np.abs(turns) >= angle_tol
    theta_c, theta_v = _lifted(a0, sweep, turns, vertex, counts)
    # edge positions: each curve, then its vertex where it has one
    nc = len(a0)
    pos_c = np.arange(nc) + np.concatenate([[0], np.cumsum(vertex)[:-1]])
    n_edges = nc + int(vertex.sum())
    curve = np.zeros(n_edges, bool)
    curve[pos_c] = True
    pos_v = pos_c[vertex] + 1
    theta = np.empty(n_edges)
    theta[pos_c], theta[pos_v] = theta_c, np.asarray(theta_v)[vertex]
    sw = np.empty(n_edges)
    sw[pos_c], sw[pos_v] = sweep, turns[vertex]
    point = np.empty((n_edges, 2))
    point[pos_c], point[pos_v] = starts, ends[vertex]
    piece_of = np.full(n_edges, -1)
    piece_of[pos_c] = np.arange(nc)
    loop_of_curve = np.repeat(np.arange(len(counts)), counts)
    loop = np.empty(n_edges, np.int64)
    loop[pos_c], loop[pos_v] = loop_of_curve, loop_of_curve[vertex]
    per_loop = np.bincount(loop, minlength=len(counts))
    index = np.arange(n_edges) - np.repeat(np.cumsum(per_loop) - per_loop, per_loop)
    return GaussTable(loop, index, curve, theta, sw, point, piece_of, curves, len(loops))


def _lifted(a0, sweep, turns, vertex, counts, rounds=8):
    """(theta of each curve edge, theta of its vertex edge (0.0 where none)): the
    lifted angles along each loop, each start angle moved by whole turns to continue
    the previous edge's end (:func:`_wrap`'s rule; the float operations of walking
    each loop edge by edge, :func:`_lifted_walk`).

    The walk's step from one edge to the next is done for all edges at once, from
    a guess of every edge's angle (a0 less the whole turns counted along the loop,
    :func:`_whole_turns`), until the angles stop changing: a fixed point of the step
    is the walk's result (each loop's first angle is a0, and each next one the step
    of the one before).  Each round makes at least the next angle after the last
    right one right, so a loop is done within as many rounds as it has wrong
    guesses in a row (the guess is mostly right to the bit: most angles are a0
    moved by zero turns); loops not done within ``rounds`` rounds are walked."""
    first = np.cumsum(counts) - counts
    head = np.zeros(len(a0), bool)
    head[first[counts > 0]] = True
    theta = a0 - TWO_PI * _whole_turns(a0, sweep, turns, vertex, counts, first)
    for _ in range(rounds):
        ends = theta + sweep
        ends = np.where(vertex, ends + turns, ends)
        prev = np.roll(ends, 1)
        d = a0 - prev
        step = prev + (d - TWO_PI * np.ceil((d - np.pi) / TWO_PI))
        step[head] = a0[head]
        if np.array_equal(step.view(np.int64), theta.view(np.int64)):   # to the bit
            return theta, np.where(vertex, theta + sweep, 0.0)
        theta = step
    theta_c, theta_v = _lifted_walk(a0.tolist(), sweep.tolist(), turns.tolist(),
                                    vertex.tolist(), counts.tolist())
    return np.array(theta_c), np.array(theta_v)


def _whole_turns(a0, sweep, turns, vertex, counts, first):
    """The whole turns k (floats) of :func:`_lifted`'s guess a0 - 2 pi k: each join's
    (the ceil of _wrap's rule on the unlifted angles: a0 of the next curve less the
    end of this one, a0 + sweep + its turn, which differ from whole turns by less
    than angle_tol, far from the ceil's rounding point) summed along each loop."""
    ends = a0 + sweep + np.where(vertex, turns, 0.0)
    step = np.zeros(len(a0))
    step[1:] = np.ceil((a0[1:] - ends[:-1] - np.pi) / TWO_PI)
    step[first[counts > 0]] = 0.0
    k = np.cumsum(step)
    return k - np.repeat(k[first], counts)


def _lifted_walk(a0, sweep, turns, vertex, counts):
    """:func:`_lifted` edge by edge along each loop (lists in, lists out)."""
    theta_c, theta_v = [0.0] * len(a0), [0.0] * len(a0)
    lo = 0
    for n in counts:
        theta = a0[lo]
        for i in range(lo, lo + n):
            if i > lo:
                d = a0[i] - theta
                theta = theta + (d - TWO_PI * math.ceil((d - np.pi) / TWO_PI))
            theta_c[i] = theta
            theta = theta + sweep[i]
            if vertex[i]:
                theta_v[i] = theta
                theta = theta + turns[i]
        lo += n
    return theta_c, theta_v


#: a turn within this of pi is a cusp (radians), its side read from the curves
#: (:func:`_cusp_sides`), not from the sign of the turn.  End tangents come from
#: control points, and coordinates rounded to 1e-3 of a handle's length (as SVG
#: and font files store them) turn them by up to ~1e-3 rad: a turn that close to pi
#: may be a cusp whose sides cross a hair from its point, where the sign of the turn
#: says the wrong side (an icon's notch read as a spike).  For a genuine corner the
#: side test agrees with the sign; so this bounds only how many corners pay for the
#: test, not what the Gauss map is.
CUSP_ANGLE = 1e-3


def _corner_turns_many(curves, counts, a0, sweep, last, traced=0):
    """Turn at the end of each curve (the loops' curves one after the other,
    ``counts`` per loop), cusps resolved (see :func:`gauss_map`): the turns of all
    loops at once, the sides of all near-cusps at once (:func:`_cusp_sides`), the
    open cusps of all loops at once (:func:`_open_cusp_turns_many`).  ``a0``,
    ``sweep``: start angle and sweep of each curve; ``last``: its unit end tangent.
    The open cusps of the first ``traced`` loops, paths traced out and back, turn
    +pi without that test: such a loop winds 0 round every point off its trace
    (the probe beyond a tip is outside) and has area 0 (counts as counter-
    clockwise), so its tips stick out, which is what the test would find (it was
    half of the Gauss map's time of a stroke font, the winding numbers of probes
    at every stroke's two ends)."""
    first_of = np.repeat(np.cumsum(counts) - counts, counts)
    k = np.arange(len(curves))
    nxt = np.where(k + 1 - first_of == np.repeat(counts, counts), first_of, k + 1)
    turns = _wrap(a0[nxt] - (a0 + sweep))
    cusp = np.flatnonzero(np.abs(turns) > np.pi - CUSP_ANGLE)
    if not len(cusp):
        return turns
    side = _cusp_sides(_taken(curves, cusp), _taken(curves, nxt[cusp]))
    flip = (side != 0) & (side * turns[cusp] < 0)  # the same tangents, turned the other way
    turns[cusp[flip]] += side[flip] * TWO_PI
    open_cusps = cusp[side == 0]
    if len(open_cusps):
        loop_of = np.repeat(np.arange(len(counts)), counts)
        tip = loop_of[open_cusps] < traced
        turns[open_cusps[tip]] = np.pi
        open_cusps = open_cusps[~tip]
    if len(open_cusps):
        turns[open_cusps] = _open_cusp_turns_many(curves, counts, loop_of, open_cusps,
                                                  last[open_cusps])
    return turns


def _open_cusp_turns_many(curves, counts, loop_of, open_cusps, ways):
    """Turns (+-pi) at the ends of curves where the loop runs back along itself (its
    two ways coincide: a spike, a slit, the ends of a centre line traced out and
    back), as the set the loop traces has them: the tip of a part of zero width
    sticking out of the loop's filled side is convex (+pi for a counter-clockwise
    loop), one cut into it is reflex (-pi).  Which it is: the loop's winding number
    at a probe just beyond the tip (1e-6 of the loop's size along the way in, the
    loop flattened within a tenth of that): 0 outside.  A loop of area 0 counts as
    counter-clockwise, and its tips stick out without a probe (it winds 0 round
    every point off its trace).  Where the loop does not bound what it traces (a part of zero
    width crossing the rest of the loop) the turns then do not add up to one full
    turn, and :func:`morph.convolve.gauss_pair_of` refuses it.

    All loops with open cusps at once: each is moved so that its first point is at
    the origin and scaled by 1 / its size (homogeneous x, y; the same curves), so
    that one flattening tolerance (1e-7) and one area threshold (1e-9) serve every
    loop, and stacked 4 apart in y (a loop then spans at most 1 in x and y), so that
    the horizontal rays of one loop's probes (:func:`morph.polyline.
    winding_number`) meet no other loop.  ``ways``: the unit end tangents of the
    curves ``open_cusps``."""
    curves = pc.Pieces.of(curves)
    loops = pl.unique(loop_of[open_cusps])
    begin = np.cumsum(counts) - counts
    owner = np.repeat(np.arange(len(loops)), counts[loops])
    within = np.cumsum(counts[loops]) - counts[loops]
    idx = begin[loops][owner] + np.arange(len(owner)) - within[owner]
    groups = [(ks, h.copy()) for ks, h in _taken(curves, idx).groups]
    size = _loop_sizes(groups, owner, len(loops))
    origin = pc.end_points(_taken(curves, begin[loops]))[0]
    shift = np.column_stack([np.zeros(len(loops)), 4.0 * np.arange(len(loops))])
    terms = np.zeros(len(idx))
    for ks, h in groups:
        o = owner[ks]
        h[..., :2] = (h[..., :2] - origin[o][:, None] * h[..., 2:]) / size[o][:, None, None]
        # about the loop's first point
        terms[ks] = mo.area_terms(pc.Pieces([(np.arange(len(h)), h.copy())], len(h)))
        h[..., :2] += shift[o][:, None] * h[..., 2:]
    moved = pc.Pieces(groups, len(idx))
    area = np.bincount(owner, weights=terms, minlength=len(loops))
    sign = np.where(np.abs(area) > 1e-9, np.sign(area), 1.0)
    eps = 1e-6
    where = np.searchsorted(loops, loop_of[open_cusps])
    tips = pc.end_points(_taken(curves, open_cusps))[1]
    tips = (tips - origin[where]) / size[where][:, None] + shift[where]
    ways = ways / np.maximum(np.hypot(*ways.T), 1e-300)[:, None]
    probes = tips + eps * ways
    # a loop of area 0 winds 0 round every point off its trace: its tips are all
    # outside without a probe, which could land on the trace itself (a closed path
    # traced out and back has both tips where the path runs on through them)
    outside = (np.abs(area) <= 1e-9)[where]
    probed = np.flatnonzero(~outside)
    if len(probed):
        outside[probed] = _probes_outside(groups, moved, owner, probes[probed],
                                          where[probed], len(loops), eps)
    return np.where(outside, np.pi, -np.pi) * sign[where]



def _probes_outside(groups, moved, owner, probes, where, n_loops, eps):
    """Whether each probe (of loop ``where``) has winding number 0 round its loop
    (``moved``: the loops' pieces as :func:`_open_cusp_turns_many` moves them,
    ``groups`` by degree, ``owner`` each piece's loop).  Only the pieces whose
    control box holds a probe of their loop are flattened finely (within a tenth of
    eps); the others become their chord: the region between a piece and its chord
    lies in the piece's control hull, so no probe outside that hull changes its
    winding number when the piece is replaced by its chord (the probe's winding is
    the exact loop's wherever the fine flattening's is)."""
    fine = _boxes_holding_probes(groups, owner, probes, where, len(owner), n_loops,
                                 0.1 * eps)
    polys = _loop_polylines(moved, owner, fine, n_loops, 0.1 * eps)
    return np.round(winding_number(probes, polys)) == 0

def _loop_sizes(groups, owner, n_loops):
    """(n_loops,) the larger side of each loop's control-point box (``owner``: each
    piece's loop; ``groups``: (indices, stacked homogeneous control points) per
    degree)."""
    lo = np.full((n_loops, 2), np.inf)
    hi = np.full((n_loops, 2), -np.inf)
    for ks, h in groups:
        x = h[..., :2] / h[..., 2:]
        np.minimum.at(lo, owner[ks], x.min(axis=1))
        np.maximum.at(hi, owner[ks], x.max(axis=1))
    return np.maximum(np.max(hi - lo, axis=1), 1e-300)


def _loop_polylines(moved, owner, fine, n_loops, tol):
    """Each loop as one polyline: its ``fine`` pieces flattened within ``tol``, the
    others by their start point only (their chord)."""
    f_idx = np.flatnonzero(fine)
    f_owner, f_t, f_pts = pl.flat_starts(_taken(moved, f_idx), tol)
    c_idx = np.flatnonzero(~fine)
    piece_of = np.concatenate([f_idx[f_owner], c_idx])
    t = np.concatenate([f_t, np.zeros(len(c_idx))])
    pts = np.concatenate([f_pts, pc.end_points(_taken(moved, c_idx))[0]
                          if len(c_idx) else np.zeros((0, 2))])
    order = np.lexsort((t, piece_of))       # the loops' pieces in order, each's vertices
    bounds = np.searchsorted(owner[piece_of[order]], np.arange(n_loops + 1))
    pts = pts.take(order, axis=0)
    polys = [pts[a:b] for a, b in zip(bounds[:-1], bounds[1:])]
    return polys


def _boxes_holding_probes(groups, owner, probes, where, n_pieces, n_loops, margin):
    """(n_pieces,) bools: the pieces whose control box, grown by ``margin``, holds a
    probe of their own loop (``owner``: each piece's loop, ``where``: each probe's);
    ``groups``: (indices, stacked homogeneous control points) per degree."""
    fine = np.zeros(n_pieces, bool)
    by_loop = np.argsort(where, kind="stable")
    count = np.bincount(where, minlength=n_loops)
    first_probe = np.cumsum(count) - count
    for ks, h in groups:
        x = h[..., :2] / h[..., 2:]
        blo, bhi = x.min(axis=1) - margin, x.max(axis=1) + margin
        n = count[owner[ks]]                     # (piece, probe of its loop) pairs
        piece = np.repeat(np.arange(len(ks)), n)
        probe = by_loop[np.repeat(first_probe[owner[ks]], n) + np.arange(n.sum())
                        - np.repeat(np.cumsum(n) - n, n)]
        hit = ((probes[probe] >= blo[piece]) & (probes[probe] <= bhi[piece])).all(axis=1)
        fine[ks[pl.unique(piece[hit])]] = True
    return fine


def _cusp_sides(c_ins, c_outs):
    """For each cusp (the end of ``c_ins[k]``, where ``c_outs[k]`` starts): +1 if
    the way out lies left of the way in, -1 right, 0 coincident; (k,) ints.

    Both ways leave the cusp point X backwards along the incoming direction d; the
    angles of their points seen from X (measured from -d) are compared at
    parameter steps 1e-2, 1e-4, 1e-6, the first clear difference deciding: the
    largest step, so that two ways crossing a hair from X (a sliver below the
    flattening's resolution, which no crossing test sees) are read by where they
    run beyond the crossing, not by their end tangents.  Both curves
    are evaluated moved so that X is the origin: the points' rounding then scales
    with the curves' size, not with X's distance from (0, 0) (far from it, a
    path traced back on itself would otherwise seem to turn to a random side).
    All cusps at once, the curves evaluated by degree groups (:func:`_points_at`).
    """
    c_ins, c_outs = pc.Pieces.of(c_ins), pc.Pieces.of(c_outs)
    k = len(c_ins)
    x = pc.end_points(c_ins)[1]
    c_ins, c_outs = _moved(c_ins, -x), _moved(c_outs, -x)
    back = -pc.end_tangents_many(c_ins)[1]
    side = np.zeros(k, np.int64)
    todo = np.ones(k, bool)
    for delta in (1e-2, 1e-4, 1e-6):
        a = _points_at(c_ins, 1.0 - delta)
        b = _points_at(c_outs, delta)
        phi_a = np.arctan2(back[:, 0] * a[:, 1] - back[:, 1] * a[:, 0], np.sum(back * a, axis=1))
        phi_b = np.arctan2(back[:, 0] * b[:, 1] - back[:, 1] * b[:, 0], np.sum(back * b, axis=1))
        clear = todo & (np.abs(phi_b - phi_a) > 1e-7)
        side[clear] = np.where(phi_b[clear] < phi_a[clear], 1, -1)
        todo &= ~clear
        if not todo.any():
            break
    return side


def _moved(pieces, offsets):
    """Each piece moved by its offset (k, 2) (:func:`morph.piece.translate`: the same
    operations, pieces of one degree at once), as a :class:`morph.piece.Pieces`."""
    groups = []
    for ks, h in pieces.groups:
        h = h.copy()
        h[:, :, 0] += offsets[ks, 0][:, None] * h[:, :, 2]
        h[:, :, 1] += offsets[ks, 1][:, None] * h[:, :, 2]
        groups.append((ks, h))
    return pc.Pieces(groups, len(pieces))


def _points_at(pieces, t):
    """Points of many pieces at one parameter t, (k, 2): pieces of one degree at once."""
    out = np.zeros((len(pieces), 2))
    for ks, h in pc.degree_groups(pieces):
        n = h.shape[1]
        v = np.einsum("j,kjc->kc", bz.basis(n - 1, np.array([t]))[0], h)
        out[ks] = v[:, :2] / v[:, 2:]
    return out


def total_turning(edges):
    """Sum of sweeps: +2 pi for a counter-clockwise simple loop, -2 pi for a hole."""
    return float(sum(e.sweep for e in edges))


def angle_param(piece, theta):
    """Parameter t where the tangent angle of a monotone piece equals theta.

    Solves cross(H(t), d) = 0 with d = (cos theta, sin theta) for the hodograph
    direction H (Eq. 27 specialised to one curve); on a monotone piece (from
    :func:`split_monotone`, |sweep| <= pi/2) the root is unique and H points along
    d there.  Scalar form of :func:`angle_params`.
    """
    h = pc.tangent_numerator(np.asarray(piece, float))
    return float(angle_params(h[None], np.array([theta], float))[0])


def angle_params(h, theta, distinct=False):
    """:func:`angle_param` for many pieces at once, from their tangent numerators.

    h: (k, m+1, 2) tangent numerators (``piece.tangent_numerator``, elevated to one
    degree m; elevation leaves the direction unchanged); theta: (k,).  Returns t
    (k,): f = cross(d, H) is a Bernstein polynomial; an end where |f| <= 1e-14
    max|f_i| is taken as is; where f changes sign over [0, 1] the root comes from a
    bracketed Newton iteration (:func:`morph.bernstein.solve_bracketed`); otherwise
    theta lies (numerically) outside the range and the closer end is returned.
    ``distinct``: the rows are known to be distinct (each equal row would be solved
    once, :func:`_solved_once`, which then only costs its sort).
    """
    h = np.asarray(h, float)
    theta = np.asarray(theta, float)
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    f = h[:, :, 1] * c - h[:, :, 0] * s
    scale = np.abs(f).max(axis=1)
    f0, f1 = f[:, 0], f[:, -1]
    t = np.where(np.abs(f0) < np.abs(f1), 0.0, 1.0)
    t = np.where(np.abs(f1) <= 1e-14 * scale, 1.0, t)
    t = np.where(np.abs(f0) <= 1e-14 * scale, 0.0, t)
    inner = (f0 * f1 < 0) & (np.abs(f0) > 1e-14 * scale) & (np.abs(f1) > 1e-14 * scale)
    if inner.any():
        t[inner] = bz.solve_bracketed(f[inner]) if distinct else _solved_once(f[inner])
    return t


def _solved_once(f):
    """:func:`morph.bernstein.solve_bracketed` of the rows of ``f``, each distinct
    row (to the bit) solved once: a font's strokes share directions (a third to a
    half of a hanzi chunk's rows repeat), and a row's root depends on the row
    alone."""
    if len(f) < 64:
        return bz.solve_bracketed(f)
    bits = np.ascontiguousarray(f).view(np.int64)      # rows equal to the bit
    order = np.lexsort(bits.T[::-1])
    step = np.ones(len(f), bool)
    step[1:] = (bits[order[1:]] != bits[order[:-1]]).any(axis=1)
    if step.all():
        return bz.solve_bracketed(f)
    group = np.empty(len(f), np.int64)
    group[order] = np.cumsum(step) - 1
    return bz.solve_bracketed(f[order[step]])[group]


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

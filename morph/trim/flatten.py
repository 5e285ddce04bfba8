"""Tagged polylines on an integer grid: the input of the polygon engine.

Every closed loop of rational pieces becomes a closed polyline whose vertices lie
on the pieces (certified flattening, :func:`morph.piece.flatten_many`: each piece
is within ``eps`` of its polyline by the convex-hull property of positive-weight
rational Béziers), snapped to the integer grid ``round((p - origin) / grid)``.
Each vertex keeps its tag (piece index, parameter t); each segment runs from its
vertex to the next one of its loop and carries the parameter range [t0, t1] on the
piece of its start vertex.  Vertices that fall into one grid point are merged,
keeping the start of a piece where there is one (a piece shorter than the grid
vanishes and its neighbours meet at the grid point).  Segments are then routed
through the grid points of the other vertices whose pixels they cross (snap
rounding with the vertices' pixels hot): two segments closer than a grid step keep
their order or coincide, where rounding their ends on their own could swap them.
"""

from dataclasses import dataclass

import numpy as np

from .. import piece as pc
from ..polyline import BoxGrid


@dataclass
class Tagged:
    """Closed polylines of all loops, on the integer grid.

    q (N, 2) int64 grid coordinates; piece (N,) index into ``pieces``; t0, t1 (N,)
    parameter range of segment i (from vertex i to vertex ``nxt[i]``) on
    ``pieces[piece[i]]``; nxt, prv (N,) next / previous vertex of the same loop;
    starts (L+1,) offsets of the loops; origin (2,) and grid: float = origin + grid * q;
    eps: the flattening bound (each segment within eps of its piece before rounding).
    """

    q: np.ndarray
    piece: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    nxt: np.ndarray
    prv: np.ndarray
    starts: np.ndarray
    origin: np.ndarray
    grid: float
    pieces: list
    eps: float = 0.0

    def to_float(self, q):
        return self.origin + self.grid * np.asarray(q, float)

    def paths(self):
        """The loops as lists of integer points (pyclipper's input)."""
        return [self.q[a:b] for a, b in zip(self.starts[:-1], self.starts[1:])]


def tag_loops(loops, eps, grid, origin=None):
    """:class:`Tagged` polylines of closed loops of pieces (see the module docstring).

    eps: flattening bound (absolute); grid: size of one integer unit.  Loops that
    collapse to fewer than three grid points are dropped (their area is below
    grid^2 times their vertex count).
    """
    pieces = [np.asarray(p, float) for loop in loops for p in loop]
    # a closed loop's polyline: its pieces' polylines without their ends (the next
    # piece's start), in order
    pid, ts, xy = pc.flat_starts(pieces, eps)
    loop_of = np.repeat(np.arange(len(loops)), [len(loop) for loop in loops])[pid]
    if origin is None:
        origin = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
    origin = np.asarray(origin, float)
    q = np.rint((xy - origin) / grid).astype(np.int64)
    keep = _merge_equal(q, ts == 0.0, loop_of)
    q, pid, ts, loop_of, xy = q[keep], pid[keep], ts[keep], loop_of[keep], xy[keep]
    # loops with fewer than three vertices enclose nothing on the grid
    counts = np.bincount(loop_of, minlength=len(loops))
    ok = counts[loop_of] >= 3
    q, pid, ts, loop_of, xy = q[ok], pid[ok], ts[ok], loop_of[ok], xy[ok]
    nxt, prv, starts = _links(loop_of)
    if len(q):
        q, pid, ts, loop_of = _through_hot_pixels(q, (xy - origin) / grid, pid, ts, loop_of, nxt)
        nxt, prv, starts = _links(loop_of)
    # a segment ends at its next vertex's parameter on the same piece, 1 at a piece's
    # last vertex; a vertex put on a segment at its start (a hot pixel beside it)
    # shares the start's parameter: that range is empty, not [t, 1] (which would lift
    # a one-unit edge as the whole rest of the piece)
    same = (pid[nxt] == pid) & (ts[nxt] >= ts)
    t1 = np.where(same, ts[nxt], 1.0)
    return Tagged(q, pid, ts, t1, nxt, prv, starts, origin, float(grid), pieces, float(eps))


def _links(loop_of):
    """(nxt, prv, starts) of closed loops stored one after another (loop_of sorted)."""
    first = np.flatnonzero(np.diff(loop_of, prepend=-1))
    starts = np.append(first, len(loop_of))
    idx = np.arange(len(loop_of))
    nxt = idx + 1
    nxt[starts[1:] - 1] = starts[:-1]
    prv = idx - 1
    prv[starts[:-1]] = starts[1:] - 1
    return nxt, prv, starts


def _through_hot_pixels(q, x, pid, ts, loop_of, nxt):
    """Each segment routed through the grid points of the vertices whose pixels (unit
    squares around them) its unrounded form crosses: snap rounding (Hobby) with the
    vertices' pixels hot.

    Rounding each vertex on its own can invert two segments closer than a grid
    step (a needle of two near-coincident legs whose ends round apart: its inside
    changes winding, an open crack in a filled region).  Through the same hot
    pixels, such legs round to the same grid path, and near-parallel segments keep
    their order.  x: unrounded positions in grid units; a vertex put on a segment
    gets that segment's piece and a parameter interpolated along it.  The rounded
    polyline stays within sqrt(2) / 2 grid units of the unrounded one.
    """
    a, b = x, x[nxt]
    grid = BoxGrid(np.minimum(a, b) - 0.5, np.maximum(a, b) + 0.5)
    hot, hot_of = _unique_rows(q)
    h, s = grid.at_points(hot.astype(float))
    c = hot[h].astype(float)
    # boxes (widened by half a pixel) that hold the pixel's centre, not at own ends
    keep = np.flatnonzero((grid.lo[s, 0] < c[:, 0]) & (grid.hi[s, 0] > c[:, 0])
                          & (grid.lo[s, 1] < c[:, 1]) & (grid.hi[s, 1] > c[:, 1])
                          & (hot_of[s] != h) & (hot_of[nxt[s]] != h))
    h, s, c = h[keep], s[keep], c[keep]
    keep = _line_crosses_square(a[s], b[s], c)
    h, s, c = h[keep], s[keep], c[keep]
    if not len(s):
        return q, pid, ts, loop_of
    d = b[s] - a[s]
    u = np.clip(np.einsum("ij,ij->i", c - a[s], d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300),
                0.0, 1.0)
    t_end = np.where((pid[nxt[s]] == pid[s]) & (ts[nxt[s]] > ts[s]), ts[nxt[s]], 1.0)
    # the new vertices after their segment's start, in order along it
    n = len(q)
    order = np.lexsort((np.concatenate([np.zeros(n), u]),
                        np.concatenate([np.zeros(n, np.int8), np.ones(len(s), np.int8)]),
                        np.concatenate([np.arange(n), s])))
    q = np.concatenate([q, hot[h]])[order]
    pid = np.concatenate([pid, pid[s]])[order]
    ts = np.concatenate([ts, ts[s] + u * (t_end - ts[s])])[order]
    loop_of = np.concatenate([loop_of, loop_of[s]])[order]
    return q, pid, ts, loop_of


def _unique_rows(q):
    """(distinct rows of an (n, 2) integer array, the index of each row among them)."""
    o = np.lexsort((q[:, 1], q[:, 0]))
    r = q[o]
    new = np.concatenate(([True], np.any(r[1:] != r[:-1], axis=1)))
    of = np.empty(len(q), np.int64)
    of[o] = np.cumsum(new) - 1
    return r[new], of


def _line_crosses_square(a, b, c):
    """Whether the lines through a and b cross the unit squares centred at c (not
    just touch): |d x (c - a)| < (|d_x| + |d_y|) / 2, d = b - a.  For a segment
    whose box overlaps the square, the same as the segment crossing it."""
    d, w = b - a, c - a
    return np.abs(d[:, 0] * w[:, 1] - d[:, 1] * w[:, 0]) < 0.5 * (np.abs(d[:, 0]) + np.abs(d[:, 1]))


def _merge_equal(q, is_start, loop_of):
    """Indices to keep: one vertex per run of equal consecutive grid points of a loop
    (cyclic), the last piece start in the run if any, else its first vertex."""
    keep = []
    bounds = np.flatnonzero(np.diff(loop_of)) + 1
    for a, b in zip(np.concatenate([[0], bounds]), np.concatenate([bounds, [len(q)]])):
        lq = q[a:b]
        same = np.all(lq == np.roll(lq, 1, axis=0), axis=1)
        if same.all():
            continue  # the whole loop is one grid point
        r = int(np.argmin(same))  # a run begins here
        order = np.roll(np.arange(a, b), -r)
        same = np.roll(same, -r)
        run_first = np.flatnonzero(~same)
        cand = np.where(is_start[order], np.arange(len(order)), -1)
        best = np.maximum.reduceat(cand, run_first)
        keep.append(order[np.where(best >= 0, best, run_first)])
    return np.sort(np.concatenate(keep)) if keep else np.zeros(0, np.int64)

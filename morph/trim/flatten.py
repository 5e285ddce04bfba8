"""Tagged polylines on an integer grid: the input of the polygon engine.

Every closed loop of rational pieces becomes a closed polyline whose vertices lie
on the pieces (certified flattening, :func:`morph.piece.flatten_many`: each piece
is within ``eps`` of its polyline by the convex-hull property of positive-weight
rational Béziers), snapped to the integer grid ``round((p - origin) / grid)``.
Each vertex keeps its tag (piece index, parameter t); each segment runs from its
vertex to the next one of its loop and carries the parameter range [t0, t1] on the
piece of its start vertex.  Vertices that fall into one grid point are merged,
keeping the start of a piece where there is one (a piece shorter than the grid
vanishes and its neighbours meet at the grid point).
"""

from dataclasses import dataclass

import numpy as np

from .. import piece as pc


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
    q, pid, ts, loop_of = q[keep], pid[keep], ts[keep], loop_of[keep]
    # loops with fewer than three vertices enclose nothing on the grid
    counts = np.bincount(loop_of, minlength=len(loops))
    ok = counts[loop_of] >= 3
    q, pid, ts, loop_of = q[ok], pid[ok], ts[ok], loop_of[ok]
    first = np.flatnonzero(np.diff(loop_of, prepend=-1))  # loop_of is sorted, >= 0
    starts = np.append(first, len(q))
    idx = np.arange(len(q))
    nxt = idx + 1
    nxt[starts[1:] - 1] = starts[:-1]
    prv = idx - 1
    prv[starts[:-1]] = starts[1:] - 1
    same = (pid[nxt] == pid) & (ts[nxt] > ts)
    t1 = np.where(same, ts[nxt], 1.0)
    return Tagged(q, pid, ts, t1, nxt, prv, starts, origin, float(grid), pieces, float(eps))


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

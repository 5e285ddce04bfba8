"""All the pieces of an export batch as per-degree arrays (a *bank*), and the loop
plan (corners, smooth runs) computed on them for every loop at once.

The exporters get lists of loops of (n+1, 3) pieces.  They are concatenated once
(one ``np.concatenate``) and gathered into one stack per degree; every per-piece
quantity the export needs (checks, polynomial and line flags, end points, end
tangents, sizes, which joins are smooth) is then an array operation over the stacks,
not a Python loop over the pieces.  A piece keeps its *global* index (its position
in the concatenation); ``deg[g]`` and ``idx[g]`` say where it sits in the stacks.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import math
from collections import namedtuple

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from ..polyline import unique


class Bank:
    """Pieces of mixed degree as one stack per degree.

    ``stacks[n]``: (k_n, n, 3) homogeneous control points of the pieces with n
    control points; ``deg[g]``, ``idx[g]``: the stack and the row of global piece g;
    ``pieces[g]``: the piece itself (as given, checked); ``degrees`` the sorted keys
    of ``stacks``.  Per piece (arrays over g): ``poly`` (weights equal to 1e-12:
    polynomial), ``first`` and ``last`` (end points), ``t_first`` and ``t_last``
    (unit end tangents, zero for a piece without a direction), ``d_ends`` (2, g, 2)
    (first derivatives at t = 0 and t = 1, :func:`end_pair`), ``lo`` and ``hi``
    (bounding box corners) and ``scale`` (largest absolute Cartesian coordinate).
    ``order``: the pieces of the searched chains, concatenated (set by
    :func:`morph.export.fit.make_chains`; None before).
    """

    def __init__(self, pieces):
        pieces = list(pieces)
        self.pieces = pieces
        g = len(pieces)
        sizes = np.fromiter(map(len, pieces), int, g)
        try:
            flat = np.concatenate(pieces, axis=0).astype(float) if g else np.zeros((0, 3))
            bad = flat.ndim != 2 or flat.shape[1] != 3 or np.any(sizes < 2)
        except ValueError:
            bad = True
        if bad or not np.all(np.isfinite(flat)) or np.any(flat[:, 2] <= 0):
            from .certify import check_piece

            for p in pieces:           # the first bad piece names the error
                check_piece(p)
        offsets = np.concatenate([[0], np.cumsum(sizes)])
        self.deg = sizes
        self.idx = np.empty(g, int)
        self.stacks = {}
        self.poly = np.empty(g, bool)
        self.first, self.last = np.empty((g, 2)), np.empty((g, 2))
        self.t_first, self.t_last = np.zeros((g, 2)), np.zeros((g, 2))
        self.lo, self.hi = np.empty((g, 2)), np.empty((g, 2))
        self.scale = np.empty(g)
        self.bend = np.zeros(g)
        self.d_ends = np.empty((2, g, 2))       # first derivatives at t = 0 and t = 1
        for n in unique(sizes).tolist():
            rows = np.nonzero(sizes == n)[0]
            self.idx[rows] = np.arange(len(rows))
            at = offsets[rows][None] + np.arange(n)[:, None]          # (n, k)
            self.stacks[n] = flat.take(at.T, axis=0)                   # (k, n, 3)
            x, y, w = flat.T.take(at, axis=1)                          # (n, k) each
            self.poly[rows] = np.logical_and.reduce(np.abs(w - w[0]) <= 1e-12 * np.abs(w[0]))
            x, y = x / w, y / w
            self.first[rows, 0], self.first[rows, 1] = x[0], y[0]
            self.last[rows, 0], self.last[rows, 1] = x[-1], y[-1]
            lo = np.array([x.min(axis=0), y.min(axis=0)]).T
            hi = np.array([x.max(axis=0), y.max(axis=0)]).T
            self.lo[rows], self.hi[rows] = lo, hi
            self.scale[rows] = np.maximum(np.abs(lo), np.abs(hi)).max(axis=1)
            self.t_first[rows], self.t_last[rows] = _end_tangents(x, y, (hi - lo).max(axis=1))
            self.bend[rows] = _bend(x, y)
            self.d_ends[:, rows] = end_pair(self.stacks[n])
        self.line = (sizes == 2) & self.poly
        self.degrees = sorted(self.stacks)   # the stacks' sizes, ascending
        self._nodes = None              # node_planes' cache
        self.order = None               # the searched chains' pieces (make_chains)

    def cartesian(self, gids):
        """Cartesian control points of the pieces ``gids``, a list of (n, 2) arrays
        (one division per degree)."""
        gids = np.asarray(gids, int)
        out = np.empty(len(gids), object)
        for rows, h in self.gather(gids):
            out[rows] = list(h[..., :2] / h[..., 2:])
        return list(out)

    def gather(self, gids):
        """The pieces ``gids`` as a list of (rows, stack): rows of ``gids`` per degree
        and their control points (k, n, 3)."""
        gids = np.asarray(gids, int)
        if not gids.shape[0]:
            return []
        if len(self.degrees) == 1:          # one stack: every row
            return [(np.arange(gids.shape[0]),
                     self.stacks[self.degrees[0]].take(self.idx[gids], axis=0))]
        deg = self.deg[gids]
        count = np.bincount(deg, minlength=self.degrees[-1] + 1).tolist()
        # the degrees present, ascending; ``rows`` the one array of nonzero's tuple
        return [(rows, self.stacks[n].take(self.idx[gids[rows]], axis=0))
                for n in self.degrees if count[n] for rows in (deg == n).nonzero()]

    def jet(self, gids, t):
        """Points and first derivatives of pieces ``gids`` at parameters ``t`` (one
        evaluation per degree: a piece's result does not depend on the batch)."""
        gids = np.asarray(gids, int)
        p, d = np.empty((len(t), 2)), np.empty((len(t), 2))
        for rows, h in self.gather(gids):
            p[rows], d[rows] = pc.jet_rows(h, t[rows])
        return p, d


    def jet_grid(self, gids, t):
        """Points and first derivatives of every piece ``gids`` at the same parameters
        t (q,): arrays (len(gids), q, 2) (:meth:`jet_planes`, interleaved)."""
        planes = self.jet_planes(gids, t)
        return planes[:2].transpose(2, 1, 0), planes[2:].transpose(2, 1, 0)

    def jet_planes(self, gids, t):
        """Points and first derivatives of every piece ``gids`` at the same parameters
        t (q,) as planes (4, q, len(gids)): x, y, x', y' (:func:`grid_planes`, the
        Bernstein bases at t made once per degree)."""
        gids = np.asarray(gids, int)
        t = np.asarray(t, float)
        out = np.empty((4, len(t), len(gids)))
        for rows, h in self.gather(gids):
            n = h.shape[1] - 1
            out[:, :, rows] = grid_planes(h, bz.basis(n, t), bz.basis(n - 1, t))
        return out

    def node_planes(self, gids, t):
        """:meth:`jet_planes` of pieces ``gids`` at parameters t, each piece evaluated
        once per bank: the fitter samples every whole piece of a range at the same
        nodes, round after round.  On the first call every piece of the searched
        chains (``order``, :func:`morph.export.fit.make_chains`; without it every
        piece that is not a line) is evaluated (one call per degree for the whole
        bank, not a few per round for the pieces a round meets first; pieces written
        as they are, or cut off at corners, are not); a piece's result does not
        depend on the batch, so a cached one is the one a round would compute."""
        gids = np.asarray(gids, int)
        t = np.asarray(t, float)
        if self._nodes is None or not (t is self._nodes[0] or np.array_equal(self._nodes[0], t)):
            g = len(self.deg)
            self._nodes = (t, np.zeros(g, bool), np.empty((4, len(t), g)))
            pool = (~self.line).nonzero()[0] if self.order is None else self.order
            gids_all = np.concatenate([pool, gids])
        else:
            gids_all = gids
        _, have, planes = self._nodes
        if not np.logical_and.reduce(have[gids_all]):     # some not evaluated yet
            need = unique(gids_all[~have[gids_all]])
            planes[:, :, need] = self.jet_planes(need, t)
            have[need] = True
        return planes.take(gids, axis=2)         # contiguous rows (not [:, :, gids])


def end_pair(h):
    """First derivatives (2, k, 2) of the rational pieces h (k, n+1, 3) at t = 0 and
    at t = 1, from their end control points: H' = n (h_1 - h_0) (and n (h_n -
    h_{n-1})), then the quotient rule (the numbers :func:`morph.piece.jet_rows` gives
    there: its basis rows are exact ones and zeros)."""
    n = h.shape[1] - 1
    val = np.array([h[:, 0], h[:, -1]])
    dval = n * np.array([h[:, 1] - h[:, 0], h[:, -1] - h[:, -2]])
    w = val[..., 2:3]
    return (dval[..., :2] * w - val[..., :2] * dval[..., 2:3]) / w ** 2


def grid_planes(h, b, db, major=None):
    """Points and first derivatives of the rational pieces h (k, n+1, 3) at the
    parameters whose Bernstein bases of degrees n and n - 1 are ``b`` (q, n+1) and
    ``db`` (q, n): planes (4, q, k) of x, y, x', y', a piece per column (``major``:
    None, or h's C-contiguous coefficient-major copy (n+1, 3, k), not made again).

    The homogeneous value H = sum_j B_j h_j and derivative H' = n sum_j B'_j (h_{j+1}
    - h_j) are summed control point by control point (elementwise: a piece's values
    do not depend on the batch), then x = X / W and x' = (X' - x W') / W.  The sums
    are node-major (q, 3, k): each term is one basis value times a contiguous row of
    3 k coordinates, the one broadcast numpy runs without buffering."""
    k, m, _ = h.shape
    q = b.shape[0]
    hc = np.ascontiguousarray(h.transpose(1, 2, 0)) if major is None else major  # (n+1, 3, k)
    dh = (m - 1) * (hc[1:] - hc[:-1])
    if m * q * 3 * k <= GRID_FUSED:
        hom, der = _fused_sums(hc, dh, b, db)
    else:
        hom, der = np.zeros((2, q, 3, k))
        tmp = np.empty_like(hom)
        for acc, coef, basis in ((hom, hc, b), (der, dh, db)):
            for j in range(coef.shape[0]):
                acc += np.multiply(coef[j], basis[:, j, None, None], out=tmp)
    out = np.empty((4, q, k))
    node = out.transpose(1, 0, 2)                                  # (q, 4, k) view
    w = hom[:, 2:]
    np.divide(hom[:, :2], w, out=node[:, :2])
    np.multiply(node[:, :2], der[:, 2:], out=node[:, 2:])
    np.subtract(der[:, :2], node[:, 2:], out=node[:, 2:])
    node[:, 2:] /= w
    return out


#: Products per sum (control points times nodes times 3 k coordinates) up to which
#: :func:`grid_planes` makes all terms of a sum in one call (a few hundred KB: a
#: round's cut parts); larger batches multiply term by term into one (q, 3, k)
#: buffer that stays in cache.
GRID_FUSED = 1 << 16


def _fused_sums(hc, dh, b, db):
    """The sums of :func:`grid_planes` (q, 3, k) each: every product of a coefficient
    and a basis value in one call per sum, then added to 0 one control point after
    the other (the accumulator's numbers)."""
    out = []
    for coef, basis in ((hc, b), (dh, db)):
        terms = coef[:, None] * basis.T[:, :, None, None]          # (n + 1, q, 3, k)
        acc = np.add(terms[0], 0.0)
        for term in terms[1:]:
            acc += term
        out.append(acc)
    return out


def _bend(x, y):
    """L theta^5 of each piece's control polygon, its control points' coordinate
    planes x, y (n, k): its length L and its turning theta (the sum of the absolute
    angles between consecutive edges), which bound the piece's arc length and
    turning (variation diminishing).  A cubic fitted to a circular arc of length L
    turning theta misses it by about c L theta^5 (c a constant):
    :func:`morph.export.search.first_widths` sums (L theta^5 / tol)^(1/6) over a
    chain's pieces to guess how many cubics it needs."""
    ex, ey = np.diff(x, axis=0), np.diff(y, axis=0)
    length = np.hypot(ex, ey).sum(axis=0)
    if len(x) < 3:
        return np.zeros(x.shape[1])
    ax, ay, bx, by = ex[:-1], ey[:-1], ex[1:], ey[1:]
    turn = np.abs(np.arctan2(ax * by - ay * bx, ax * bx + ay * by)).sum(axis=0)
    return length * turn ** 5


def _end_tangents(x, y, size, rel=1e-12):
    """:func:`morph.piece.end_tangents_many` (not strict) of Cartesian control points,
    the coordinate planes x, y (n, k) of one degree (``size`` the larger side of
    each one's bounding box): along the first and the last control-point difference
    longer than ``rel`` times the piece's size; zero vectors where all control
    points coincide."""
    dx, dy = np.diff(x, axis=0), np.diff(y, axis=0)
    n = np.hypot(dx, dy)
    ok = n > rel * size
    dead = ~ok.any(axis=0) | (size <= 1e-300)
    i0 = np.argmax(ok, axis=0)
    i1 = len(dx) - 1 - np.argmax(ok[::-1], axis=0)
    r = np.arange(x.shape[1])
    out = []
    for i in (i0, i1):
        length = np.where(dead, 1.0, n[i, r])
        t = np.array([dx[i, r], dy[i, r]]).T / length[:, None]
        out.append(np.where(dead[:, None], 0.0, t))
    return out


def smooth_joins(bank, starts, counts, angle):
    """Per global piece whether its join to the next piece of its loop is smooth
    (the last piece of a loop: its closing join to the loop's first piece): the
    pieces meet within 1e-12 of the coordinates and their tangent directions differ
    by less than ``angle`` radians.  ``starts``, ``counts``: each loop's first
    global piece and number of pieces (the loops' pieces consecutive)."""
    g = len(bank.deg)
    nxt = np.arange(1, g + 1)
    ends = starts + counts - 1
    nxt[ends[counts > 0]] = starts[counts > 0]
    a, b = bank.t_last, bank.t_first[nxt]
    gap = np.hypot(*(bank.last - bank.first[nxt]).T)
    return (((a * b).sum(axis=1) > 0)
            & (np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) <= math.sin(angle))
            & (gap <= 1e-12 * (1.0 + np.maximum(bank.scale, bank.scale[nxt]))))


#: The runs of a batch as arrays (:func:`plan_run_arrays`): ``order`` the global piece
#: ids of all runs concatenated, ``sizes`` each run's number of pieces, ``exact``
#: whether it is written as it is, ``loop`` the loop it belongs to (runs in loop
#: order, each loop's in order).
RunArrays = namedtuple("RunArrays", "order sizes exact loop")


def plan_run_arrays(loops, join_angle, wrap):
    """The runs of every loop, computed for all loops at once: (bank,
    :class:`RunArrays`), no Python step per run.

    A loop is split where a join is not smooth (:func:`smooth_joins`) and around
    every line (a polynomial piece of degree 1 is a run of its own); with ``wrap``
    and ``join_angle > 0`` a loop's last run and first are one when its closing join
    is smooth and neither end piece is a line (that run is the loop's first: the
    last run's pieces, then the first's).  ``exact``: every piece of the run is
    polynomial of degree <= 3 (written as it is, not fitted)."""
    counts = np.fromiter(map(len, loops), int, len(loops))
    bank = Bank([p for loop in loops for p in loop])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(int)
    g = len(bank.deg)
    smooth = (smooth_joins(bank, starts, counts, join_angle) if join_angle > 0
              else np.zeros(g, bool))
    cont = np.zeros(g, bool)                       # piece i continues the run of i - 1
    if g > 1:
        cont[1:] = ~bank.line[1:] & ~bank.line[:-1] & smooth[:-1]
    cont[starts[counts > 0]] = False
    heads = np.nonzero(~cont)[0]                   # first piece of every run
    tails = np.append(heads[1:], g)
    fine = bank.poly & (bank.deg <= 4)
    bad_before = np.concatenate([[0], np.cumsum(~fine)])
    run_exact = (bad_before[tails] - bad_before[heads]) == 0
    loop_of = np.repeat(np.arange(len(loops)), counts)[heads] if g else np.zeros(0, int)
    first_run = np.searchsorted(loop_of, np.arange(len(loops)))
    last_run = np.searchsorted(loop_of, np.arange(len(loops)), side="right") - 1
    merge = np.zeros(len(loops), bool)
    if wrap and join_angle > 0 and g:
        ends = starts + counts - 1
        merge = ((last_run - first_run >= 1) & ~bank.line[np.maximum(ends, 0)]
                 & ~bank.line[np.minimum(starts, g - 1)] & smooth[np.maximum(ends, 0)])
    # a merged loop: its last run moves to the place of its first, which follows it
    key = np.arange(len(heads), dtype=float)
    key[last_run[merge]] = first_run[merge] - 0.5
    keep = np.ones(len(heads), bool)
    keep[first_run[merge]] = False
    primary = np.nonzero(keep)[0]
    primary = primary[np.argsort(key[primary], kind="stable")]
    second = np.full(len(heads), -1)
    second[last_run[merge]] = first_run[merge]
    second = second[primary]
    # the runs' segments (primary, then its second where merged) and their pieces
    seg = np.stack([primary, second], axis=1).ravel()
    seg = seg[seg >= 0]
    length = tails[seg] - heads[seg]
    order = (np.repeat(heads[seg] - (np.cumsum(length) - length), length)
             + np.arange(int(length.sum())))
    has = second >= 0
    sizes = tails[primary] - heads[primary]
    sizes[has] += tails[second[has]] - heads[second[has]]
    exact = run_exact[primary] & np.where(has, run_exact[np.maximum(second, 0)], True)
    return bank, RunArrays(order, sizes, exact, loop_of[primary])


def plan_runs(loops, join_angle, wrap):
    """:func:`plan_run_arrays` as (bank, runs) with ``runs`` a list per loop of
    (global piece ids, exact) in order."""
    bank, runs = plan_run_arrays(loops, join_angle, wrap)
    parts = np.split(runs.order, np.cumsum(runs.sizes)[:-1]) if len(runs.sizes) else []
    out = [[] for _ in loops]
    for ids, e, i in zip(parts, runs.exact.tolist(), runs.loop.tolist()):
        out[i].append((ids, e))
    return bank, out

"""Convolution curves of two regions (Sec. 3.3) with the QAC method (Sec. 4.4).

The convolution C1 * C2 is the set of sums C1(t) + C2(s) where the tangents (so the
normals) point the same way (Def. 1.1, Eqs. 2-4).  Each loop is first turned into its
Gauss map (:mod:`morph.gauss`); every pair of edges of the two Gauss maps whose angle
ranges overlap contributes one convolution piece:

- curve + curve: approximated by QAC (:mod:`morph.qac`, Sec. 4.4; the subdivision
  driver of :mod:`morph.subdivide`), normals exact;
- curve + vertex: the curve translated by the vertex (exact);
- line + anything: the segment translated by the other edge's point at its angle;
- vertex + vertex: a single point, dropped.

Direction (Figs. 18-19): a piece made from edge X (traversed as in its loop) and edge
Y runs along X's own direction when Y is convex (sign > 0) and against it when Y is
concave, as in polygon convolution (edge + vertex takes the sign of the vertex's
turn).  This gives convex/convex pairs their inherited direction, reverses
concave/convex pairs where the concave side has the larger curvature, and reverses
concave/concave pairs, so every convolution loop is consistently oriented.

Type (Fig. 20): 1 for convex/convex (straight segments count as convex here), 2 for
convex/concave, 3 for concave/concave or concave/straight pairs and pairs with a
concave vertex.  Type 3 pieces never reach the Minkowski sum boundary.

Equal angles are resolved by a symbolic perturbation: every angle of the second shape
is taken as if increased by an infinitesimal epsilon, so a straight edge of A at
angle theta pairs with the edge of B whose range is (lo, hi] around theta, a straight
edge of B with A's [lo, hi), and two parallel segments never pair directly.  This
keeps the pieces of one loop pair chained end to end.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""


import numpy as np

from . import bernstein as bz
from . import gauss
from . import piece as pc
from . import qac
from .errors import SelfCrossingError, ToleranceNotMetError
from .subdivide import ConvPiece, subdivide_nodes
from .polyline import unique

ANGLE_EQ = 1e-9      # angles closer than this are equal (radians)


# ---------------------------------------------------------------- edge pairing

class _EdgeTable:
    """The edges of several loops' Gauss maps as arrays, one row per edge.

    loop, index: the loop and the edge's index in it.  curved: curve edges that
    turn (sweep != 0); straight: curve edges with sweep 0; vertex: corners.
    deg, slot: each curve edge's piece is ``stacks[deg][slot]``.  h: tangent
    numerators of the curved edges (``piece.tangent_numerator``), elevated to one
    degree (zeros elsewhere), for :func:`morph.gauss.angle_params`.
    """

    def __init__(self, maps):
        edges = [e for m in maps for e in m]
        self._edges = edges
        self.n_loops = len(maps)
        self.loop = np.repeat(np.arange(len(maps)), [len(m) for m in maps])
        self.index = np.concatenate([np.arange(len(m)) for m in maps]) if maps else np.zeros(0, int)
        is_curve = np.array([e.kind == "curve" for e in edges], bool)
        self.theta = np.array([e.theta for e in edges], float)
        self.sweep = np.array([e.sweep for e in edges], float)
        self.lo = np.minimum(self.theta, self.theta + self.sweep)
        self.hi = np.maximum(self.theta, self.theta + self.sweep)
        self.sign = np.sign(self.sweep).astype(int)
        self.point = np.array([np.asarray(e.point, float) for e in edges]).reshape(-1, 2)
        self.vertex = ~is_curve
        self.straight = is_curve & (self.sweep == 0.0)
        self.curved = is_curve & (self.sweep != 0.0)
        n = len(edges)
        self.deg = np.full(n, -1)
        self.slot = np.zeros(n, int)
        self.stacks = {}
        lists = {}
        for i in np.nonzero(is_curve)[0]:
            p = np.asarray(edges[i].piece, float)
            d = len(p) - 1
            lst = lists.setdefault(d, [])
            self.deg[i], self.slot[i] = d, len(lst)
            lst.append(p)
        self.stacks = {d: np.array(lst) for d, lst in lists.items()}
        self.h = self._tangent_numerators()

    @classmethod
    def of_gauss(cls, g):
        """The table of a :class:`morph.gauss.GaussTable` (the same arrays as of its
        :class:`morph.gauss.Edge` lists, made without them)."""
        self = cls.__new__(cls)
        self._edges, self._gauss = None, g
        self.n_loops = g.n_loops
        self.loop, self.index = g.loop, g.index
        is_curve = g.curve
        self.theta, self.sweep = g.theta, g.sweep
        self.lo = np.minimum(self.theta, self.theta + self.sweep)
        self.hi = np.maximum(self.theta, self.theta + self.sweep)
        self.sign = np.sign(self.sweep).astype(int)
        self.point = g.point
        self.vertex = ~is_curve
        self.straight = is_curve & (self.sweep == 0.0)
        self.curved = is_curve & (self.sweep != 0.0)
        n = len(g)
        self.deg = np.full(n, -1)
        self.slot = np.zeros(n, int)
        self.stacks = {}
        edge_of = np.flatnonzero(is_curve)          # curve k is edge edge_of[k]
        for ks, h in g.curves.groups:               # ks ascending: edge order
            d = h.shape[1] - 1
            self.deg[edge_of[ks]] = d
            self.slot[edge_of[ks]] = np.arange(len(ks))
            self.stacks[d] = h
        self.h = self._tangent_numerators()
        return self

    @property
    def edges(self):
        """The :class:`morph.gauss.Edge` objects, in table order (made when asked)."""
        if self._edges is None:
            self._edges = [e for m in self._gauss.maps() for e in m]
        return self._edges

    def pieces(self, idx):
        """Stacks of the pieces of edges idx, grouped by degree: [(rows, stack)]."""
        out = []
        deg = self.deg[idx]
        for d in unique(deg):
            rows = np.nonzero(deg == d)[0]
            out.append((rows, self.stacks[d].take(self.slot[idx[rows]], axis=0)))
        return out

    def _tangent_numerators(self):
        idx = np.nonzero(self.curved)[0]
        parts = []
        for rows, st in self.pieces(idx):
            poly = pc.is_polynomial_many(st)
            for sel, rational in ((poly, False), (~poly, True)):
                if sel.any():
                    h = pc.tangent_numerator_many(st.compress(sel, axis=0), rational)
                    redo = np.nonzero(pc.end_zero_rows(h))[0]
                    hs = list(h) if len(redo) else h
                    for r in redo:
                        hs[r] = pc.tangent_numerator(st[sel][r])   # ends divided out
                    parts.append((idx[rows[sel]], hs))
        # the largest degree: an array's width, or of a list (rows redone) its longest row
        deg = max([(hs.shape[1] if isinstance(hs, np.ndarray) else max(map(len, hs))) - 1
                   for _, hs in parts], default=0)
        out = np.zeros((len(self.loop), deg + 1, 2))
        for ids, hs in parts:
            if isinstance(hs, np.ndarray) and hs.shape[1] in (1, deg + 1):
                # elevating degree 0 to deg multiplies by exactly 1 (bz.to_degree)
                out[ids] = hs
                continue
            for i, h in zip(ids, hs):
                out[i] = bz.to_degree(h, deg)
        return out

    def params(self, idx, angle, distinct=False):
        """Parameters of the curved edges idx where their tangent angle is ``angle``
        (an angle within 1e-13 of the edge's start or end angle gives that end, as
        :func:`morph.gauss.restrict`); ``distinct``: no (edge, angle) pair repeats
        (:func:`morph.gauss.angle_params`)."""
        t = (gauss.angle_params(self.h.take(idx, axis=0), angle, distinct) if len(idx)
             else np.zeros(0))
        return self._at_ends(idx, angle, t)

    def _at_ends(self, idx, angle, t):
        """``t`` with the angles within 1e-13 of an edge's end angle at that end."""
        t = np.where(np.abs(angle - (self.theta[idx] + self.sweep[idx])) < 1e-13, 1.0, t)
        return np.where(np.abs(angle - self.theta[idx]) < 1e-13, 0.0, t)

    def params_many(self, requests):
        """:meth:`params` of each ``(idx, angle)`` of ``requests``, all in one call: an
        angle several requests share (a stroke's straight edge and the ends of its
        two vertices' ranges meet the nib at its direction) is solved once
        (:func:`morph.gauss.angle_params`; each row's result is its own)."""
        return params_of_tables([(self, requests)])[0]

    def restricted(self, idx, t_lo, t_hi):
        """Sub-pieces of the curved edges idx between the parameters at their angles
        lo and hi, in each edge's direction: [(rows, stack)] by degree."""
        t0, t1 = self._directed(idx, t_lo, t_hi)
        # each (edge, t0, t1) once: a font's strokes share directions, so the ranges
        # of the nib's edges at their corners repeat (half the rows of a hanzi chunk)
        first, group = _distinct_rows(np.asarray(idx, np.int64), t0.view(np.int64),
                                      t1.view(np.int64))
        deg, where, out = self.deg[idx], np.empty(len(first), np.int64), []
        for rows, st in self.pieces(idx[first]):
            sub = bz.subsegment_many(st, t0[first[rows]], t1[first[rows]])
            where[rows] = np.arange(len(rows))
            mine = np.flatnonzero(deg == deg[first[rows[0]]])
            out.append((mine, sub.take(where[group[mine]], axis=0)))
        return out

    def _directed(self, idx, t_lo, t_hi):
        """(t0, t1): the parameters at angles lo, hi in each edge's direction."""
        conv = self.sweep[idx] > 0
        return np.where(conv, t_lo, t_hi), np.where(conv, t_hi, t_lo)

    def points_at(self, idx, angle, t=None):
        """Point of each edge idx with tangent angle ``angle`` (:func:`gauss.point_at_angle`);
        ``t``: the parameters of its curved ones (:meth:`params`), where known."""
        pts = self.point.take(idx, axis=0)
        cur = np.nonzero(self.curved[idx])[0]
        if len(cur):
            if t is None:
                t = self.params(idx[cur], angle[cur])
            for rows, st in self.pieces(idx[cur]):
                v = bz.evaluate_many(st, t[rows])
                pts[cur[rows]] = v[:, :2] / v[:, 2:3]
        return pts


def _distinct_rows(*keys):
    """(one row of each distinct tuple of the int64 arrays ``keys``, the group of each
    row: its tuple's place in that list).  The rows are sorted by one number mixing
    the keys (each step: times an odd constant, xor the next key): equal tuples mix
    equal, so they come together; two distinct tuples that mix equal (which the
    check finds) send the rows to a sort by all the keys instead."""
    mix = keys[0]
    with np.errstate(over="ignore"):
        for k in keys[1:]:
            mix = k ^ (mix * np.int64(-7046029254386353131))
    order = np.argsort(mix, kind="stable")
    m_s = mix[order]
    tie = m_s[1:] == m_s[:-1]
    differ = np.zeros(len(tie), bool)
    for k in keys:
        k_s = k[order]
        differ |= k_s[1:] != k_s[:-1]
    if (differ & tie).any():
        order = np.lexsort(keys[::-1])
        tie = np.ones(len(order) - 1, bool)
        for k in keys:
            k_s = k[order]
            tie &= k_s[1:] == k_s[:-1]
    step = np.ones(len(order), bool)
    step[1:] = ~tie
    group = np.empty(len(order), np.int64)
    group[order] = np.cumsum(step) - 1
    return order[step], group


def _pair_table(ta, tb, block=1 << 21):
    """All compatible pairs of the edges of two tables (every loop of A with every
    loop of B): arrays (i, j, lo, hi, k) in the order of :func:`compatible_pairs`
    applied loop pair by loop pair (loops of A, then of B; proper pairs, then A's
    straight edges, then B's; row-major within each).  Each class compares only
    the edges it can pair (:func:`_class_pairs`)."""
    a_line, b_line = ta.straight, tb.straight
    a_rest, a_str = np.flatnonzero(~a_line), np.flatnonzero(a_line)
    b_rest, b_str = np.flatnonzero(~b_line), np.flatnonzero(b_line)
    parts = [x for cls, rows, cols in ((0, a_rest, b_rest), (1, a_str, b_rest),
                                       (2, a_rest, b_str))
             for x in _class_pairs(ta, tb, rows, cols, cls, block)]
    if not parts:
        z = np.zeros(0)
        return z.astype(int), z.astype(int), z, z, z
    i, j, lo, hi, k, cls = (np.concatenate(x) for x in zip(*parts))
    la, lb = ta.loop[i], tb.loop[j]
    na, nb = len(ta.lo), len(tb.lo)
    if float(ta.n_loops) * tb.n_loops * 3 * na * nb < 2.0 ** 62:
        # the five keys as one number (each pair once: distinct numbers)
        key = (((la * tb.n_loops + lb) * 3 + cls) * na + i) * nb + j
        order = np.argsort(key, kind="stable")
    else:
        order = np.lexsort((j, i, cls, lb, la))
    return i[order], j[order], lo[order], hi[order], k[order]


def _class_pairs(ta, tb, rows, cols, cls, block):
    """The pairs of one class of :func:`_pair_table` among edges ``rows`` of A and
    ``cols`` of B: (i, j, lo, hi, k, class) arrays, ``block`` comparisons at a time.
    Class 0: proper overlaps of curves and vertices; 1: a straight edge of A at
    theta with the B range (lo, hi] round it (B perturbed by +eps); 2: a straight
    edge of B at theta with the A range [lo, hi) round it."""
    if not len(rows) or not len(cols):
        return
    blo, bhi = tb.lo[cols][None, :], tb.hi[cols][None, :]
    bmid = 0.5 * (blo + bhi)
    step = max(1, block // len(cols))
    for s in range(0, len(rows), step):
        r = rows[s:s + step]
        alo, ahi = ta.lo[r, None], ta.hi[r, None]
        k = np.round((0.5 * (alo + ahi) - bmid) / gauss.TWO_PI)
        sblo = blo + gauss.TWO_PI * k
        if cls == 0:
            lo, hi = np.maximum(alo, sblo), np.minimum(ahi, bhi + gauss.TWO_PI * k)
            mask = hi - lo > ANGLE_EQ
        elif cls == 1:
            sbhi = bhi + gauss.TWO_PI * k
            mask = (alo - sblo > ANGLE_EQ) & (alo - sbhi <= ANGLE_EQ)
            lo = hi = np.broadcast_to(alo, k.shape)
        else:
            mask = (sblo - alo >= -ANGLE_EQ) & (ahi - sblo > ANGLE_EQ)
            lo = hi = sblo
        ii, jj = np.nonzero(mask)
        yield (r[ii], cols[jj], lo[ii, jj], hi[ii, jj], k[ii, jj],
               np.full(len(ii), cls))


def compatible_pairs(edges_a, edges_b):
    """Pairs (i, j, lo, hi, k) of edges whose tangent-angle ranges overlap (Sec. 3.2).

    lo, hi are in A's lifted angles; B's angles are shifted by 2 pi k.  Uses the
    epsilon rule of the module docstring for equal angles; a zero-length overlap
    (lo == hi) is returned only for straight edges, whose convolution is a
    translated segment.
    """
    i, j, lo, hi, k = _pair_table(_EdgeTable([edges_a]), _EdgeTable([edges_b]))
    return list(zip(i.tolist(), j.tolist(), lo.tolist(), hi.tolist(), k.tolist()))


def pair_type(sa, sb, a_vertex=False, b_vertex=False):
    """Fig. 20 type of a pair from the signs of its two edges (+1, 0, -1).

    Type 3 (never on the boundary): concave/concave or concave/straight pairs, and
    any pair with a concave vertex.  Works elementwise on arrays too.
    """
    sa, sb = np.asarray(sa), np.asarray(sb)
    t3 = ((np.asarray(a_vertex) & (sa < 0)) | (np.asarray(b_vertex) & (sb < 0))
          | ((sa < 0) & (sb <= 0)) | ((sb < 0) & (sa <= 0)))
    typ = np.where(t3, 3, np.where((sa >= 0) & (sb >= 0), 1, 2))
    return int(typ) if typ.ndim == 0 else typ


def _oriented(piece, forward):
    return piece if forward else pc.reverse(piece)


def _translate_many(st, offset):
    """Pieces of a stack moved by offsets (k, 2) (exact: X += ox W, Y += oy W)."""
    out = st.copy()
    out[:, :, :2] += offset[:, None, :] * st[:, :, 2:3]
    return out


def convolve_edges(ea, eb, lo, hi, shift, tol, max_depth=30, method="qac"):
    """Convolution pieces of one compatible pair of edges (A's angles lo..hi).

    ``shift`` is the multiple of 2 pi added to B's angles.  Returns a list of
    :class:`ConvPiece` (piece, bound, kind).  Curve + curve pairs go through QAC
    with subdivision of the angle range where its a-priori bound peaks (Algorithm
    4.1) until every bound <= tol; raises ToleranceNotMetError past ``max_depth``
    halvings.
    """
    ta, tb = _EdgeTable([[ea]]), _EdgeTable([[eb]])
    pairs = tuple(np.array([x]) for x in (0, 0, lo, hi, shift))
    return list(_convolve_table(ta, tb, pairs, tol, max_depth, method))


class ConvPieces:
    """Convolution pieces held as arrays, one row per piece: ``pieces`` a
    :class:`morph.piece.Pieces` (one stack per degree), ``bound`` (n,), ``kind``
    (n,) names (object array), ``type`` (n,) ints, ``row`` (n,) the pair's row in the
    table of compatible pairs, ``source`` (n, 4) (loop in A, edge, loop in B, edge),
    ``qac`` (c2, q2) or None: of each QAC piece C1(t) + Q2(s(t)) the sub-piece C2
    that Q2 replaces (a :class:`morph.piece.Pieces`) and Q2 ((n, 3, 2); NaN rows for
    the other pieces), whose distance along a part of the piece bounds the part's
    error (:func:`morph.tips.local_bounds`).
    A chunk of a font's convolution is tens of thousands of pieces: a sum keeps them
    packed from the convolution through chaining (:func:`chain` takes ``pieces``)
    and the corner pass, and makes no object per piece.  To read them one by one it
    is a sequence of :class:`ConvPiece` (made on first use)."""

    __slots__ = ("pieces", "bound", "kind", "type", "row", "source", "qac", "_objects")

    def __init__(self, pieces, bound, kind, type_, row, source, qac=None):
        self.pieces, self.bound, self.kind = pieces, bound, kind
        self.type, self.row, self.source = type_, row, source
        self.qac = qac
        self._objects = None

    def __len__(self):
        return len(self.pieces)

    def __iter__(self):
        return iter(self.objects())

    def __getitem__(self, k):
        return self.objects()[k]

    @classmethod
    def empty(cls):
        return cls(pc.Pieces([], 0), np.zeros(0), np.zeros(0, object), np.zeros(0, int),
                   np.zeros(0, int), np.zeros((0, 4), int))

    def take(self, idx):
        """The pieces ``idx`` (indices or a boolean mask), in that order."""
        idx = np.asarray(idx)
        if idx.dtype == bool:
            idx = np.flatnonzero(idx)
        taken = self.pieces.take(idx)
        # the stacks in the order of their first piece, as a list's stacks are
        taken = pc.Pieces(sorted(taken.groups, key=lambda g: g[0][0]), len(taken))
        qac = None if self.qac is None else (self.qac[0].take(idx), self.qac[1][idx])
        return ConvPieces(taken, self.bound[idx], self.kind[idx], self.type[idx],
                          self.row[idx], self.source[idx], qac)

    @staticmethod
    def concat(parts):
        """The pieces of ``parts`` (ConvPieces) one after the other."""
        parts = [p for p in parts if len(p)]
        if not parts:
            return ConvPieces.empty()
        if len(parts) == 1:
            return parts[0]
        qac = None
        if all(p.qac is not None for p in parts):
            qac = (_concat_pieces([p.qac[0] for p in parts]),
                   np.concatenate([p.qac[1] for p in parts]))
        return ConvPieces(_concat_pieces([p.pieces for p in parts]),
                          *(np.concatenate([getattr(p, f) for p in parts])
                            for f in ("bound", "kind", "type", "row", "source")), qac)

    def objects(self):
        """The pieces as a list of :class:`ConvPiece` (made once)."""
        if self._objects is None:
            bound, kind, typ = self.bound.tolist(), self.kind.tolist(), self.type.tolist()
            row, source = self.row.tolist(), [tuple(s) for s in self.source.tolist()]
            self._objects = [ConvPiece(p, bound[k], kind[k], typ[k], source[k], row[k])
                             for k, p in enumerate(self.pieces.rows())]
        return self._objects


def _concat_pieces(parts):
    """:class:`morph.piece.Pieces` of several, one after the other (one stack per
    degree, each stack's rows in ascending order as a list's stacks are)."""
    by, offset = {}, 0
    for p in parts:
        for ks, h in p.groups:
            by.setdefault(h.shape[1], []).append((ks + offset, h))
        offset += len(p)
    groups = []
    for m in sorted(by, key=lambda m: min(int(ks.min()) for ks, _ in by[m])):
        ks = np.concatenate([k for k, _ in by[m]])
        h = np.concatenate([x for _, x in by[m]])
        order = np.argsort(ks, kind="stable")
        groups.append((ks[order], h.take(order, axis=0)))
    return pc.Pieces(groups, offset)


class _Produced:
    """Convolution pieces as the pair handlers produce them: parts of (pair
    positions, sort keys, stack of one degree, bounds, kinds, production ranks);
    :meth:`packed` sorts them by (pair position, key), ties in the order produced
    (each pair's pieces in travel order)."""

    def __init__(self):
        self.parts = []
        self.count = 0

    def add(self, pos, key, stack, bound, kind, seq=None, qac=None):
        """Pieces ``stack`` (one degree); ``seq``: their ranks among the pieces
        produced since ``count`` (None: in the order given), ``count`` then moves on
        (by ``len(stack)``; the caller sets it past a batch given in parts).
        ``qac``: (c2 stack, q2) of the pieces (:class:`ConvPieces`), None for pieces
        that are no QAC pieces."""
        n = len(stack)
        seq = self.count + (np.arange(n) if seq is None else np.asarray(seq, np.int64))
        self.count += n
        if n:
            if qac is None:   # a line for C2, no Q2
                qac = (np.broadcast_to([[0.0, 0.0, 1.0]], (n, 2, 3)), np.full((n, 3, 2), np.nan))
            self.parts.append((np.asarray(pos, np.int64),
                               np.broadcast_to(np.asarray(key, float), (n,)),
                               np.asarray(stack, float),
                               np.broadcast_to(np.asarray(bound, float), (n,)),
                               np.broadcast_to(np.asarray(kind, object), (n,)), seq,
                               np.asarray(qac[0], float), np.asarray(qac[1], float)))

    def packed(self):
        """:class:`ConvPieces` in order, ``row`` the pair positions."""
        if not self.parts:
            return ConvPieces.empty()
        pos, key, seq = (np.concatenate([p[c] for p in self.parts]) for c in (0, 1, 5))
        order = np.lexsort((seq, key, pos))
        where = np.empty(len(order), np.int64)
        where[order] = np.arange(len(order))
        start = np.cumsum([0] + [len(p[0]) for p in self.parts])
        pieces = _placed(self.parts, where, start)
        bound = np.concatenate([p[3] for p in self.parts])[order]
        kind = np.concatenate([p[4] for p in self.parts])[order]
        qac = (_placed([(None, None, p[6]) for p in self.parts], where, start),
               np.concatenate([p[7] for p in self.parts])[order])
        return ConvPieces(pieces, bound, kind, np.zeros(len(order), int), pos[order],
                          np.zeros((len(order), 4), int), qac)


def _placed(parts, where, start):
    """:class:`morph.piece.Pieces` of the parts' stacks, part row r of part p going to
    ``where[start[p] + r]``."""
    by = {}
    for p, a, b in zip(parts, start[:-1], start[1:]):
        by.setdefault(p[2].shape[1], []).append((where[a:b], p[2]))
    groups = []
    for m, lst in by.items():
        ks = np.concatenate([k for k, _ in lst])
        h = np.concatenate([x for _, x in lst]) if len(lst) > 1 else lst[0][1]
        order = np.argsort(ks, kind="stable")
        groups.append((ks[order], h.take(order, axis=0)))
    groups.sort(key=lambda g: g[0][0])
    return pc.Pieces(groups, len(where))


def _convolve_table(ta, tb, pairs, tol, max_depth=30, method="qac"):
    """Convolution pieces of the pairs (i, j, lo, hi, k) of two edge tables, all at
    once: :class:`ConvPieces` (``row``: the pair's position) in the pairs' order,
    each pair's pieces in travel order (the cases of the module docstring).  tol:
    one number, or one per pair."""
    i, j, lo, hi, k = pairs
    tol = np.broadcast_to(np.asarray(tol, float), np.shape(i))
    off = gauss.TWO_PI * np.asarray(k, float)
    out = _Produced()
    curve = (np.nonzero(ta.curved[i] & tb.curved[j])[0] if method == "qac"
             else np.zeros(0, np.intp))
    moved, solved = _solved_params(ta, tb, i, j, lo, hi, off, curve)
    for p, st, points, _, forward in translated_batches(ta, tb, i, j, lo, hi, off, moved):
        _stack_out(out, p, _translate_many(st, points), forward)
    _curve_pairs(out, ta, tb, i, j, lo, hi, off, tol, max_depth, method, solved)
    return out.packed()


def _solved_params(ta, tb, i, j, lo, hi, off, curve):
    """The parameters on the curves of both tables that :func:`translated_batches`
    and :func:`qac_batches` (of the curve + curve pairs at positions ``curve``) solve,
    in one :func:`params_of_tables` call (each (edge, angle) row's parameter is its
    own: the same numbers as a call for each): (the ``moved`` argument of
    translated_batches, the ``solved`` argument of qac_batches)."""
    where, asks_a, asks_b = _translated_asks(ta, tb, i, j, lo, hi, off)
    ic, jc, lc, hc, oc = i[curve], j[curve], lo[curve], hi[curve], off[curve]
    got_a, got_b = params_of_tables([(ta, asks_a + [(ic, lc), (ic, hc)]),
                                     (tb, asks_b + [(jc, lc - oc), (jc, hc - oc)])])
    return (where, got_a[:3], got_b[:3]), (got_a[3:], got_b[3:])


def _stack_out(out, pos, stack, forward):
    """Exact pieces of a stack (sort key 0, kind "translate"), reversed where not
    ``forward``."""
    st = stack.copy() if forward.all() else np.where(forward[:, None, None], stack,
                                                     stack[:, ::-1])
    out.add(pos, 0.0, st, 0.0, "translate")


def params_of_tables(asks):
    """:meth:`_EdgeTable.params_many` of the requests of several tables (``asks``:
    [(table, requests)]), as a list per table: each table's distinct (edge, angle)
    rows (the angle to the bit), and the angle equations of all tables whose
    tangent numerators have one degree solved in one call of
    :func:`morph.gauss.angle_params` (each row's root is its own: the same numbers
    as a call per table, in one bracketed Newton iteration instead of one per
    table)."""
    rows = []
    for table, requests in asks:
        sizes = [len(idx) for idx, _ in requests]
        idx = np.concatenate([np.asarray(i, np.int64) for i, _ in requests])
        angle = np.concatenate([np.asarray(a, float) for _, a in requests])
        first, group = _distinct_rows(idx, angle.view(np.int64)) if len(idx) else (idx, idx)
        rows.append((sizes, idx[first], angle[first], group))
    solved = [None] * len(asks)
    width = [table.h.shape[1] for table, _ in asks]
    for w in unique(np.array(width)).tolist():
        which = [k for k in range(len(asks)) if width[k] == w]
        count = np.array([len(rows[k][1]) for k in which], np.int64)
        if not count.sum():
            t = np.zeros(0)
        else:
            t = gauss.angle_params(
                np.concatenate([asks[k][0].h.take(rows[k][1], axis=0) for k in which]),
                np.concatenate([rows[k][2] for k in which]), distinct=True)
        for k, part in zip(which, np.split(t, np.cumsum(count)[:-1])):
            solved[k] = part
    out = []
    for (table, _), (sizes, idx, angle, group), t in zip(asks, rows, solved):
        t = table._at_ends(idx, angle, t)[group]
        out.append(np.split(t, np.cumsum(sizes)[:-1]))
    return out


def _translated_asks(ta, tb, i, j, lo, hi, off):
    """What :func:`translated_batches` solves: ((pos_a, pos_b, ang_a, ang_b): the
    pairs whose straight edge of A, of B moves, at those angles; the requests of
    :func:`params_of_tables` on A's curves, on B's: the points at the other side's
    straight edges' angles, the ends of the ranges at the other side's vertices)."""
    pos_a = np.nonzero(ta.straight[i])[0]                  # B's point moves A's edge
    pos_b = np.nonzero(tb.straight[j] & ~ta.straight[i])[0]
    ang_a, ang_b = lo[pos_a] - off[pos_a], lo[pos_b]
    cur_a = np.nonzero(tb.curved[j[pos_a]])[0]
    cur_b = np.nonzero(ta.curved[i[pos_b]])[0]
    ranges = []                                            # a curve moved by a vertex
    for t_c, t_v, ic, iv, shift in ((ta, tb, i, j, np.zeros_like(off)),
                                    (tb, ta, j, i, off)):
        pos = np.nonzero(t_c.curved[ic] & t_v.vertex[iv])[0]
        ranges.append((ic[pos], lo[pos] - shift[pos], hi[pos] - shift[pos]))
    return ((pos_a, pos_b, ang_a, ang_b),
            [(i[pos_b][cur_b], ang_b[cur_b]), ranges[0][:2], (ranges[0][0], ranges[0][2])],
            [(j[pos_a][cur_a], ang_a[cur_a]), ranges[1][:2], (ranges[1][0], ranges[1][2])])


def translated_batches(ta, tb, i, j, lo, hi, off, moved=None):
    """The pairs whose convolution is one edge translated: a straight edge moved by
    the other edge's point at its angle, and a curve (restricted to the pair's angle
    range) moved by a vertex.  Yields (pair rows, the moved edge's piece stack, the
    points, one per row, whether the moved edge is A's, whether each piece runs
    forward: the other edge's sign).  The parameters solved on each table's curves
    (the points at the straight edges' angles, the ends of the ranges at the
    vertices) are solved together (:func:`params_of_tables`), or given: ``moved``
    (from :func:`_solved_params`)."""
    if moved is None:
        where, asks_a, asks_b = _translated_asks(ta, tb, i, j, lo, hi, off)
        moved = (where,) + tuple(params_of_tables([(ta, asks_a), (tb, asks_b)]))
    (pos_a, pos_b, ang_a, ang_b), (t_pb, t_lo_a, t_hi_a), (t_pa, t_lo_b, t_hi_b) = moved
    if len(pos_a):
        pts = tb.points_at(j[pos_a], ang_a, t_pa)
        for rows, st in ta.pieces(i[pos_a]):
            p = pos_a[rows]
            yield p, st, pts.take(rows, axis=0), True, tb.sign[j[p]] > 0
    if len(pos_b):
        pts = ta.points_at(i[pos_b], ang_b, t_pb)
        for rows, st in tb.pieces(j[pos_b]):
            p = pos_b[rows]
            yield p, st, pts.take(rows, axis=0), False, ta.sign[i[p]] > 0
    for t_c, t_v, ic, iv, t_lo, t_hi, of_a in ((ta, tb, i, j, t_lo_a, t_hi_a, True),
                                               (tb, ta, j, i, t_lo_b, t_hi_b, False)):
        pos = np.nonzero(t_c.curved[ic] & t_v.vertex[iv])[0]
        if not len(pos):
            continue
        subs = t_c.restricted(ic[pos], t_lo, t_hi)
        for rows, st in subs:
            p = pos[rows]
            yield p, st, t_v.point.take(iv[p], axis=0), of_a, t_v.sign[iv[p]] > 0


def _curve_pairs(out, ta, tb, i, j, lo, hi, off, tol, max_depth, method, solved=None):
    """Curve + curve pairs: QAC (:func:`_qac_pairs`; ``solved``: its parameters, from
    :func:`_solved_params`) or another method of Sec. 4 (:func:`_method_range`, pair
    by pair)."""
    pos = np.nonzero(ta.curved[i] & tb.curved[j])[0]
    if not len(pos):
        return
    if method == "qac":
        _qac_pairs(out, ta, tb, pos, i[pos], j[pos], lo[pos], hi[pos], off[pos], tol,
                   max_depth, solved)
        return
    for p in pos:
        pieces = _method_range(ta.edges[i[p]], tb.edges[j[p]], lo[p], hi[p], off[p],
                               float(tol[p]), max_depth, method)
        for r, c in enumerate(pieces):
            out.add([p], float(r), np.asarray(c.piece, float)[None], c.bound, c.kind)


def _method_range(ea, eb, lo, hi, off, tol, depth, method):
    """Curve + curve pair by one of the other methods of Sec. 4 (morph.paper.methods).

    Algorithm 5.1 on the pair (A's edge is C1); each piece's ``bound`` is the error it
    reached, sampled (not a bound) for every method but QAC.  Pieces come in A's
    direction of travel and are reversed, with their order, when B is concave.  A
    common sweep below TINY_SWEEP gives the chord of the sums (:func:`qac.chord_piece`).
    """
    ca = gauss.restrict(ea, lo, hi)[0]
    cb = gauss.restrict(eb, lo - off, hi - off)[0]
    forward = eb.sign > 0
    if hi - lo < qac.TINY_SWEEP:
        piece, bound = qac.chord_piece(ca, cb, ea.sign, eb.sign)
        return [ConvPiece(_oriented(piece, forward), bound, "chord")]
    from .paper.methods import approximate  # the paper's methods: only for --method

    out = approximate(ca, cb, method, tol, max_depth=depth)
    for c in out:
        c.piece, c.c1, c.c2 = _oriented(c.piece, forward), None, None
    return out if forward else out[::-1]


def qac_batches(ta, tb, pos, i, j, lo, hi, off, tol, max_depth, piece_of, stacked=False,
                solved=None):
    """Algorithm 4.1's subdivision of curve + curve pairs (tables ``ta``, ``tb``; pair
    rows ``i``, ``j`` over the angle ranges [lo, hi], B's angles shifted by ``off``;
    ``tol`` per row), one batch per pair of piece degrees: yields the
    :func:`morph.subdivide.subdivide_nodes` result (accepted nodes, their
    ``piece_of`` results, bounds) of each batch (``stacked``: ``piece_of`` works on
    arrays, as :func:`morph.qac.piece_stacks`, and the pieces come as a
    :class:`morph.piece.Pieces`).  ``solved``: the parameters at the ends of the
    ranges on A's and B's edges (:func:`_solved_params`), else solved here.  The
    two sides' tangent numerators, where of one degree, are restricted in one call."""
    if solved is None:
        solved = params_of_tables([(ta, [(i, lo), (i, hi)]), (tb, [(j, lo - off), (j, hi - off)])])
    (ta_lo, ta_hi), (tb_lo, tb_hi) = solved
    ha, hb = qac.stacked_calls(bz.subsegment_many, [
        (ta.h.take(i, axis=0),) + ta._directed(i, ta_lo, ta_hi),
        (tb.h.take(j, axis=0),) + tb._directed(j, tb_lo, tb_hi)])
    for da, db in sorted(set(zip(ta.deg[i].tolist(), tb.deg[j].tolist()))):
        rows = np.nonzero((ta.deg[i] == da) & (tb.deg[j] == db))[0]
        nodes = {"ca": ta.restricted(i[rows], ta_lo[rows], ta_hi[rows])[0][1],
                 "cb": tb.restricted(j[rows], tb_lo[rows], tb_hi[rows])[0][1],
                 "ha": ha[rows], "hb": hb[rows], "sa": ta.sign[i[rows]],
                 "sb": tb.sign[j[rows]], "lo": lo[rows], "hi": hi[rows],
                 "t0": np.zeros(len(rows)), "t1": np.ones(len(rows)), "pos": pos[rows],
                 "tol": tol[rows]}
        yield subdivide_nodes(nodes, piece_of, qac.bound_nodes, qac.split_nodes,
                              float(tol[rows].min()), max_depth, stacked)


def _qac_pairs(out, ta, tb, pos, i, j, lo, hi, off, tol, max_depth, solved=None):
    """Algorithm 4.1 on curve + curve pairs, all pairs and sub-ranges of one level
    together: each pair restricted to its common angle range, then the driver
    :func:`morph.subdivide.subdivide_nodes` with :mod:`morph.qac`'s callables (role
    choice, a-priori bound, split where it peaks), one batch per pair of piece
    degrees.  Adds to ``out`` (:class:`_Produced`) each piece with its pair
    position and a sort key that orders each pair's pieces along its travel
    direction (increasing angle when the two edges turn the same way); a piece runs
    along A's edge, reversed when B is concave (Figs. 18-19).
    """
    names = np.array(qac.KIND_NAMES, object)
    for done, pieces, bounds in qac_batches(ta, tb, pos, i, j, lo, hi, off, tol[pos],
                                            max_depth, qac.piece_stacks, stacked=True,
                                            solved=solved):
        key = np.where(done["sa"] * done["sb"] > 0, done["lo"], -done["lo"])
        forward = done["sb"] > 0
        base = out.count
        c2, q2 = _replaced(done)
        for ks, st in pc.degree_groups(pieces):
            st = np.where(forward[ks][:, None, None], st, st[:, ::-1])
            out.count = base
            out.add(done["pos"][ks], key[ks], st, np.asarray(bounds, float)[ks],
                    names[done["kind"][ks]], seq=ks, qac=(c2[ks], q2[ks]))
        out.count = base + len(pieces)


def _replaced(done):
    """(C2 (k, n+1, 3), Q2 (k, 3, 2)) of accepted nodes: the sub-piece QAC replaced
    by a quadratic and that quadratic (:func:`morph.qac.bound_nodes`' role), both
    sides' pieces elevated to one degree; Q2 NaN for the nodes of other kinds."""
    ca, cb = done["ca"], done["cb"]
    n = max(ca.shape[1], cb.shape[1])
    ca, cb = bz.elevate_many(ca, n - ca.shape[1]), bz.elevate_many(cb, n - cb.shape[1])
    c2 = np.where(done["swap"][:, None, None], ca, cb)
    q2 = np.where((done["kind"] == qac.QAC)[:, None, None], done["q2"], np.nan)
    return c2, q2


# ------------------------------------------------------------------ whole loops

def _convolve_all(ta, tb, table, tol, keep_type3, method, rows=None):
    """:class:`ConvPieces` of the pairs of a pair table (those of ``rows`` only, when
    given), typed (Fig. 20), in its order.  tol: one number, or one per row of the
    table."""
    row = np.arange(len(table[0])) if rows is None else np.asarray(rows, int)
    tol = np.broadcast_to(np.asarray(tol, float), (len(table[0]),))[row]
    table = tuple(np.asarray(x)[row] for x in table)
    i, j = table[0], table[1]
    typ = pair_type(ta.sign[i], tb.sign[j], ta.vertex[i], tb.vertex[j])
    if not keep_type3:
        keep = typ != 3
        table, typ, row, tol = tuple(x[keep] for x in table), typ[keep], row[keep], tol[keep]
        i, j = table[0], table[1]
    try:
        out = _convolve_table(ta, tb, table, tol, method=method)
    except ToleranceNotMetError as exc:
        if exc.rows is not None:    # the failing pairs' rows of the table
            exc.rows = row[np.asarray(exc.rows, np.int64)]
        raise
    p = out.row
    out.type = np.asarray(typ, int)[p]
    out.source = np.stack([ta.loop[i][p], ta.index[i][p], tb.loop[j][p], tb.index[j][p]],
                          axis=1).astype(int).reshape(-1, 4)
    out.row = row[p]
    return out


def convolution(region_a, region_b, tol, keep_type3=True, method="qac", gauss_pair=None,
                rows=None):
    """Convolution pieces of two regions (lists of loops), Sec. 3.3, as
    :class:`ConvPieces` (arrays; a sequence of :class:`ConvPiece` to read).

    Each returned piece P has max distance to the exact convolution curve <= tol
    (a-priori bound of Eqs. 39-40; see :func:`morph.qac.qac_error_bound`); normals are exact
    except on "chord" pieces (common sweep below 1e-7 rad).  tol is absolute, in
    input units.  With keep_type3 the pieces form closed, consistently oriented
    loops (:func:`chain`); without it type-3 pieces (never on the boundary) are
    dropped early.  All edge pairs of all loop pairs are handled together (the
    pairs found with one array comparison, Algorithm 4.1 level by level on arrays),
    in the order of the loops of A, then of B.  ``gauss_pair`` (a :class:`GaussPair`)
    gives the operands' Gauss maps and compatible pairs when they are known already
    (frames of scaled copies, :func:`scaled_gauss_pair`).  ``tol`` may also be one
    number per row of that table (each piece's ``row`` says which), and ``rows``
    (indices into the table) restricts the result to those pairs: a few pairs
    approximated again more finely (:func:`morph.minkowski.minkowski_sum` at the
    tips of wedges).
    """
    if not np.all(np.asarray(tol) > 0):
        raise ValueError("tol must be positive, got %r" % (tol,))
    if gauss_pair is None:
        gauss_pair = gauss_pair_of(region_a, region_b)
    ta, tb = gauss_pair.edge_tables()
    table = gauss_pair.table if gauss_pair.table is not None else _pair_table(ta, tb)
    return _convolve_all(ta, tb, table, tol, keep_type3, method, rows)


# ------------------------------------------------- Gauss maps shared by scaled copies

class GaussPair:
    """The Gauss maps of two operands (one list of edges per loop: ``maps_a``,
    ``maps_b``) and their table of compatible pairs (``table``, None: not computed
    yet).  Tangent angles do not change under scaling, so frames of scaled copies
    share one table (:func:`scaled_gauss_pair`).  Made from Gauss tables
    (:func:`gauss_pair_of`), the edge tables come from their arrays and the
    :class:`morph.gauss.Edge` lists are made only when read."""

    def __init__(self, maps_a=None, maps_b=None, table=None, tables=None, gauss=None):
        self._maps = [maps_a, maps_b]
        self.table, self.tables, self.gauss = table, tables, gauss

    @property
    def maps_a(self):
        return self._side(0)

    @property
    def maps_b(self):
        return self._side(1)

    def _side(self, k):
        if self._maps[k] is None:
            self._maps[k] = self.gauss[k].maps()
        return self._maps[k]

    def edge_tables(self):
        """(the edge table of A, of B) (:class:`_EdgeTable`), made once."""
        if self.tables is None:
            if self.gauss is not None:
                self.tables = tuple(_EdgeTable.of_gauss(g) for g in self.gauss)
            else:
                self.tables = (_EdgeTable(self.maps_a), _EdgeTable(self.maps_b))
        return self.tables


def gauss_pair_of(region_a, region_b, names=("operand A", "operand B"), pieces_a=None,
                  traced=False):
    """:class:`GaussPair` of two regions, the compatible pairs not computed yet.

    Raises SelfCrossingError (a ValueError) for a loop whose tangent does not turn
    through +-2 pi (the
    turning number of a simple closed curve, Hopf's Umlaufsatz): a figure-8 (0) or a
    curl (+-4 pi) crosses itself, and its convolution would bound no sum.  The
    message names the region by ``names``.  ``pieces_a``: A's pieces in order,
    stacked (a :class:`morph.piece.Pieces`, e.g. a packing's; None: stacked here).
    ``traced``: A's loops are paths traced out and back (a stroke's: the tips of
    such a loop are known, :func:`morph.gauss.gauss_table`)."""
    pieces = None if pieces_a is None else \
        pieces_a.then([p for loop in region_b for p in loop])
    g = gauss.gauss_table(list(region_a) + list(region_b), pieces=pieces,
                          traced=len(region_a) if traced else 0)
    for k, total in _off_turnings(g):
        turns = total / (2.0 * np.pi)
        if abs(abs(turns) - 1.0) > 1e-6:
            which, loop = (0, k) if k < len(region_a) else (1, k - len(region_a))
            raise SelfCrossingError(
                "%s: loop %d turns %.3g times, not once: it crosses itself; pass the loops "
                "through morph.region.orient_region (with on_crossing=morph.trim.fill_region)"
                % (names[which], loop, turns), loop)
    return GaussPair(gauss=tuple(g.split(len(region_a))))


def _off_turnings(g):
    """(loop, total turning) of the loops of a Gauss table whose total may miss +-2 pi
    by more than 2 pi 1e-6 (:meth:`morph.gauss.GaussTable.turnings`' sums, in its
    order).  The totals of all loops come from one call, in another order: two
    orders of n terms differ by at most 2 (n - 1) u sum |sweep| (u the unit
    roundoff), so a loop within twice that of the threshold is summed again as
    turnings() sums it, and the list is the same."""
    bounds = np.searchsorted(g.loop, np.arange(g.n_loops + 1))
    if not len(g.sweep):
        return []
    at = np.minimum(bounds[:-1], len(g.sweep) - 1)
    size = np.diff(bounds)
    total = np.where(size > 0, np.add.reduceat(g.sweep, at), 0.0)
    slack = 4.0 * np.finfo(float).eps * size * np.add.reduceat(np.abs(g.sweep), at)
    off = np.abs(np.abs(total) - 2.0 * np.pi) - 2.0 * np.pi * 1e-6
    sweep = g.sweep.tolist()
    return [(k, float(sum(sweep[bounds[k]:bounds[k + 1]])))
            for k in np.flatnonzero(off > -slack - 1e-300).tolist()]


def with_pair_table(pair):
    """The :class:`GaussPair` with its table of compatible pairs computed."""
    ta, tb = pair.edge_tables()
    return GaussPair(pair._maps[0], pair._maps[1], _pair_table(ta, tb), (ta, tb), pair.gauss)


def crossing_rows(gauss_pair, reach):
    """Which rows of the pair table may have a convolution piece that meets another
    piece at a junction of the trimmed boundary (a corner of the sum): a boolean per
    row, decided per convolution loop (loop a of A with loop b of B).

    A loop's convolution curve cannot cross itself when a and b are both convex and
    counter-clockwise (:func:`morph.gauss.turns_convex`: the curve is the boundary of
    the convex sum), and cannot cross another loop's when
    its box (box(a) + box(b), control points, grown by ``reach``) overlaps none of
    theirs.  The rows of every other loop are flagged.  Conservative: a row flagged
    in vain only costs work."""
    i, j = gauss_pair.table[0], gauss_pair.table[1]
    ta, tb = gauss_pair.edge_tables()
    la, lb = ta.loop[i], tb.loop[j]
    na, nb = ta.n_loops, tb.n_loops
    convex = _turn_convex(ta)[:, None] & _turn_convex(tb)[None, :]
    box = (_loop_boxes(ta)[:, None, :] + _loop_boxes(tb)[None, :, :]).reshape(-1, 4)
    box[:, :2] -= reach
    box[:, 2:] += reach
    used = np.zeros(na * nb, bool)
    used[la * nb + lb] = True
    ids = np.nonzero(used)[0]
    alone = np.ones(na * nb, bool)
    alone[ids] = _isolated(box[ids])
    return ~(convex.ravel() & alone)[la * nb + lb]


def _turn_convex(t):
    """:func:`morph.gauss.turns_convex` of each loop of an edge table (each loop's
    sweeps summed as that function sums them)."""
    bounds = np.searchsorted(t.loop, np.arange(t.n_loops + 1))
    sweep = t.sweep
    has = bounds[1:] > bounds[:-1]
    out = np.zeros(t.n_loops, bool)
    if not has.any():
        return out
    at = bounds[:-1][has]
    low = np.minimum.reduceat(sweep, at) >= -gauss.TURN_EPS
    # the sums in one call, in another order than a slice's sum: two orders of n
    # terms differ by at most 2 (n - 1) u sum |sweep| (u the unit roundoff); a loop
    # whose total is within that (doubled) of the threshold is summed again as
    # turns_convex sums it, so the answer is the same
    total = np.add.reduceat(sweep, at)
    off = np.abs(total - gauss.TWO_PI) - gauss.TURN_TOTAL_EPS
    out[has] = low & (off <= 0)
    slack = 4.0 * np.finfo(float).eps * np.diff(bounds)[has] * np.add.reduceat(np.abs(sweep), at)
    near = np.flatnonzero(low & (np.abs(off) <= slack + 1e-300))
    for k in np.flatnonzero(has)[near].tolist():
        a, b = bounds[k], bounds[k + 1]
        out[k] = abs(sweep[a:b].sum() - gauss.TWO_PI) <= gauss.TURN_TOTAL_EPS
    return out


def _isolated(box):
    """Whether each box (k, 4) overlaps no other (sort and sweep on x, then y)."""
    n = len(box)
    out = np.ones(n, bool)
    order = np.argsort(box[:, 0], kind="stable")
    stop = np.searchsorted(box[order, 0], box[order, 2], side="right")
    cnt = np.maximum(stop - np.arange(n) - 1, 0)
    p = np.repeat(np.arange(n), cnt)
    q = p + 1 + np.arange(len(p)) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    r1, r2 = order[p], order[q]
    hit = (box[r1, 1] <= box[r2, 3]) & (box[r2, 1] <= box[r1, 3])
    out[r1[hit]] = False
    out[r2[hit]] = False
    return out


def _loop_boxes(t):
    """(xmin, ymin, xmax, ymax) of each loop of an edge table: its curve edges'
    control points and its corners."""
    lo = np.full((t.n_loops, 2), np.inf)
    hi = np.full((t.n_loops, 2), -np.inf)
    for d, h in t.stacks.items():
        edges = np.flatnonzero(t.deg == d)      # in slot order
        x = h[:, :, :2] / h[:, :, 2:]
        _runs_extremes(lo, hi, t.loop[edges], x.min(axis=1), x.max(axis=1))
    v = np.flatnonzero(t.vertex)
    pv = t.point.take(v, axis=0)
    _runs_extremes(lo, hi, t.loop[v], pv, pv)
    return np.concatenate([lo, hi], axis=1)


def _runs_extremes(lo, hi, loop, low, high):
    """lo[l] = min(lo[l], low of the rows of loop l), hi likewise with max, for
    ``loop`` ascending (a table's edges are its loops' one after another): one
    reduction per run of equal loops."""
    if not len(loop):
        return
    at = np.flatnonzero(np.r_[True, loop[1:] != loop[:-1]])
    ids = loop[at]
    lo[ids] = np.minimum(lo[ids], np.minimum.reduceat(low, at, axis=0))
    hi[ids] = np.maximum(hi[ids], np.maximum.reduceat(high, at, axis=0))


def scale_edges(edges, factor):
    """The Gauss map of a loop scaled by factor > 0 about the origin: the same angles,
    scaled positions (scaling does not turn tangents)."""
    if not factor > 0:
        raise ValueError("scale factor must be positive, got %r" % (factor,))
    m = [[factor, 0.0, 0.0], [0.0, factor, 0.0]]
    return [gauss.Edge(e.kind, None if e.piece is None else pc.transform(e.piece, m),
                       factor * np.asarray(e.point, float), e.theta, e.sweep) for e in edges]


def scaled_gauss_pair(base, factor_a, factor_b):
    """``base`` (a :class:`GaussPair` of unscaled operands, table computed) for the
    operands scaled by factor_a and factor_b about the origin: positions scaled,
    angles and the table of compatible pairs shared.  The pieces of Algorithm 4.1,
    which depend on tol relative to the sizes, are not shared."""
    return GaussPair([scale_edges(e, factor_a) for e in base.maps_a],
                     [scale_edges(e, factor_b) for e in base.maps_b], base.table)


def chain(pieces, tol, packed=False):
    """Join oriented pieces end to start into closed loops (lists of arrays).
    ``pieces``: a list, or a :class:`morph.piece.Pieces` (used as it is).  With
    ``packed``: (loops, the loops' pieces one loop after another as a
    :class:`morph.piece.Pieces`, which the trimming takes without stacking the
    rows again).

    Each end is paired with a start closer than ``tol`` (nearest pairs first, each
    start used once; found by hashing the points on a grid of cell ``tol``), and the
    two are snapped to their mean.  Where several starts meet one end (loops
    touching at a point) any pairing closes the loops with the same edges, so the
    same winding numbers.  Raises TopologyError if an end has no start within tol.
    """
    from .errors import TopologyError

    pieces = pieces if isinstance(pieces, pc.Pieces) else \
        pc.Pieces.of([np.asarray(p, float) for p in pieces])
    n = len(pieces)
    if n == 0:
        return ([], pc.Pieces([], 0)) if packed else []
    starts, ends = pc.end_points(pieces)
    e, s, d = _near_pairs(ends, starts, tol)
    succ = _nearest_first(e, s, d, n, tol / TOUCH_PARTS)
    if (succ < 0).any():
        at = ends[np.argmax(succ < 0)]
        raise TopologyError("open convolution chain at %s" % (at,), loops=pieces.rows(), point=at)
    first, rank = _cycles(succ)
    order = np.lexsort((rank, first))          # loops by their lowest piece, in travel order
    # each join snapped to the mean of the end and the start meeting there
    joins = 0.5 * (ends + starts.take(succ, axis=0))    # join i: end of i, start of succ[i]
    pred = np.empty(n, np.int64)
    pred[succ] = np.arange(n)
    groups = []
    for ks, h in pc.degree_groups(pieces):
        h = h.copy()
        h[:, 0, :2] = joins.take(pred[ks], axis=0) * h[:, 0, 2:]
        h[:, -1, :2] = joins.take(ks, axis=0) * h[:, -1, 2:]
        groups.append((ks, h))
    travel = pc.Pieces(groups, n).take(order)
    ordered = travel.rows()
    bounds = [0] + (np.flatnonzero(np.diff(first[order])) + 1).tolist() + [n]
    loops = [ordered[a:b] for a, b in zip(bounds[:-1], bounds[1:])]
    return (loops, travel) if packed else loops


#: :func:`chain` takes an end and a start closer than its tol / TOUCH_PARTS as
#: meeting at one point (loops touching there): the pairs there are taken in the
#: order of the pieces, not of distances that are rounding noise of the
#: coordinates (about 1e-12 of a glyph's size), which the position of the glyph in
#: a packed sum changes
TOUCH_PARTS = 1024.0


def _nearest_first(e, s, d, n, touch=0.0):
    """succ (n,) of the pairs (end e[k], start s[k], distance d[k]) taken nearest
    first, each end and each start used once (-1: an end left without a start).
    A pair whose end and start occur in no other pair is taken whatever the order;
    only the others are decided one by one, in order of distance (the same
    result as deciding all of them so); distances below ``touch`` count as 0, the
    pairs at equal distance in the order of their end, then of their start."""
    succ = np.full(n, -1)
    lone = (np.bincount(e, minlength=n)[e] == 1) & (np.bincount(s, minlength=n)[s] == 1)
    succ[e[lone]] = s[lone]
    taken = np.zeros(n, bool)
    taken[s[lone]] = True
    rest = np.flatnonzero(~lone)
    key = np.where(d[rest] < touch, 0.0, d[rest])
    for k in rest[np.lexsort((s[rest], e[rest], key))].tolist():
        i, j = e[k], s[k]
        if succ[i] < 0 and not taken[j]:
            succ[i], taken[j] = j, True
    return succ


def _cycles(succ):
    """(first, rank) of the cycles of a permutation: each element's cycle named by
    its lowest element, and its number of steps from there along ``succ``.  The
    runs i, i + 1, ... that ``succ`` steps through in order (most of a chained
    convolution) are taken as one element each, of their length: the step out of a
    run's last element goes to another run's start.  On the runs, by pointer
    jumping (about log2 n rounds of array calls each): the lowest of 1, 2, 4 ...
    runs ahead, then the list ranking, weighted by the runs' lengths, of the cycles
    cut at their lowest run."""
    n = len(succ)
    idx = np.arange(n)
    start = np.ones(n, bool)
    start[1:] = succ[:-1] != idx[1:]
    starts = np.flatnonzero(start)
    run = np.cumsum(start) - 1                      # each element's run
    length = np.diff(np.append(starts, n))
    rsucc = run[succ[starts + length - 1]]          # the run after each run
    m = len(starts)
    ridx = np.arange(m)
    first, jump, span = ridx.copy(), rsucc.copy(), 1
    while span < m:
        first = np.minimum(first, first[jump])
        jump = jump[jump]
        span *= 2
    root = first == ridx
    pred = np.empty(m, np.int64)
    pred[rsucc] = ridx
    rank = np.where(root, 0, length[pred])
    ptr = np.where(root, ridx, pred)
    while not root[ptr].all():
        rank = rank + rank[ptr]
        ptr = ptr[ptr]
    return starts[first][run], rank[run] + (idx - starts[run])


def _near_pairs(a, b, tol):
    """Index pairs (i, j, distance) with |a_i - b_j| <= tol (grid hashing, cell tol):
    for each of the three columns of cells round a point, the three cells of the
    column are consecutive keys, found by one pair of searches; the pairs are listed
    cell by cell of the 3 x 3 neighbourhood (then by i, then by key), as nine
    searches would list them."""
    cell_a = np.floor(a / tol).astype(np.int64)
    cell_b = np.floor(b / tol).astype(np.int64)
    keys_b = cell_b[:, 0] * 3_000_017 + cell_b[:, 1]
    order = np.argsort(keys_b, kind="stable")
    sorted_keys = keys_b[order]
    keys_a = cell_a[:, 0] * 3_000_017 + cell_a[:, 1]
    # the searches take the keys in ascending order (each search then starts from the
    # previous one's place), their answers put back in the order of a
    by_a = np.argsort(keys_a)
    needles = keys_a[by_a]
    ii, jj, cc = [], [], []
    for dx in (-1, 0, 1):
        k = keys_a + dx * 3_000_017
        lo, hi = np.empty(len(a), np.int64), np.empty(len(a), np.int64)
        lo[by_a] = np.searchsorted(sorted_keys, needles + (dx * 3_000_017 - 1), "left")
        hi[by_a] = np.searchsorted(sorted_keys, needles + (dx * 3_000_017 + 1), "right")
        cnt = hi - lo
        i = np.repeat(np.arange(len(a)), cnt)
        at = np.repeat(lo, cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        ii.append(i)
        jj.append(order[at])
        cc.append(3 * (dx + 1) + 1 + (sorted_keys[at] - k[i]))   # the cell (dx, dy)
    i, j, c = np.concatenate(ii), np.concatenate(jj), np.concatenate(cc)
    d = np.hypot(*(a.take(i, axis=0) - b.take(j, axis=0)).T)
    near = np.flatnonzero(d <= tol)
    near = near[np.argsort(c[near], kind="stable")]
    return i[near], j[near], d[near]

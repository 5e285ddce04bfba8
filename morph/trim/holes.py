"""Holes of the winding-number result, decided by the exact membership predicate.

Winding numbers of the convolution curve are positive exactly on points of A ⊕ B
that some convolution loop surrounds; a cell with winding <= 0 can still lie in the
sum (a hole of one operand smaller than the other: the weak spot of Sec. 6, and of
CGAL's exact sums).  So every hole ring is tested at one interior point x, deep
inside the hole (a grid search, in the manner of polylabel's pole of
inaccessibility, stopped once the point is deep enough for the test): x ∈ A ⊕ B ⇔
A ∩ (x − B) ≠ ∅, evaluated on A and B flattened within a tenth of the point's depth
(so the answer is the exact one for x) and rounded to a grid: exact integer
predicates where the two are apart, Clipper's intersection elsewhere.
"""

import functools

import numpy as np
import pyclipper

from .. import moments as mo
from .. import piece as pc
from .. import polyline as pl
from ..polyline import (BoxGrid, _cell_pairs, columns, min_segment_distance, unique,
                        winding_number)


COARSE_VERTICES = 256  # the search runs on polygons thinned to about this many
DEPTH_REL = 0.05  # the search stops once its cells are this small against the depth


def deepest_point(ring, islands, grid_n=12, rounds=8, enough=np.inf):
    """A point inside polygon ``ring`` and outside the ``islands`` polygons (float
    (m, 2) arrays), far from all their edges, and its distance to them.

    A grid of candidates over the ring's box, refined up to ``rounds`` times around
    the best one (until a cell's half-diagonal is below DEPTH_REL times the depth
    found, or the depth is ``enough``), on the polygons thinned to every k-th vertex
    (the choice only needs to be nearly the deepest); the returned point is checked,
    and its distance measured, on the full polygons (the search is repeated on them
    if the thinned polygons misled it).
    """
    k = max(1, -(-sum(len(p) for p in [ring] + list(islands)) // COARSE_VERTICES))
    if k > 1:
        best, _ = _search(ring[::k], [i[::k] for i in islands], grid_n, rounds, enough)
        depth = _depth(best, ring, islands)
        if depth > 0.0:
            return best, depth
    return _search(ring, islands, grid_n, rounds, enough)


def deepest_points(holes, grid_n=12, rounds=8, enough=np.inf):
    """:func:`deepest_point` of many holes at once: ``holes`` a list of (ring,
    islands), returns (points (h, 2), depths (h,)), the same numbers as one call per
    hole.  Every round of the grid search runs on all holes still searching in a
    few array calls (candidates x their hole's edges); a hole whose first round
    finds no candidate inside (a thin hole between the grid points) is searched
    on its own (:func:`_search`, with its scanline fallback)."""
    n = len(holes)
    best, depth = np.zeros((n, 2)), np.full(n, -np.inf)
    polys = [[ring] + list(islands) for ring, islands in holes]
    k = [max(1, -(-sum(len(p) for p in ps) // COARSE_VERTICES)) for ps in polys]
    thin = [h for h in range(n) if k[h] > 1]
    if thin:
        x, _ = _search_many([[p[::k[h]] for p in polys[h]] for h in thin], grid_n, rounds,
                            enough)
        d = _depths(x, [polys[h] for h in thin])
        ok = d > 0.0
        best[np.array(thin)[ok]], depth[np.array(thin)[ok]] = x[ok], d[ok]
    rest = [h for h in range(n) if not depth[h] > 0.0]
    if rest:
        best[rest], depth[rest] = _search_many([polys[h] for h in rest], grid_n, rounds,
                                               enough)
    return best, depth


#: Candidates per side of :func:`points_deep_enough`'s first, coarse grid.
COARSE_GRID = 4


def points_deep_enough(holes, enough):
    """A point inside each hole (``holes``: [(ring, islands)]) and its depth, at
    least ``enough`` deep where the hole has such a point within reach of the
    search: a coarse grid (COARSE_GRID candidates a side, one round) first, which
    finds one in most holes of a glyph (the hole test needs no deeper point:
    every point that deep gets the same answer), then :func:`deepest_points` for
    the others (a ninth of the candidates for the most of them).  The coarse
    grid runs on the polygons as they are (few candidates: no thinning) and
    leaves the holes it finds no candidate inside to the second search."""
    if not holes:
        return np.zeros((0, 2)), np.zeros(0)
    x, depth = _search_many([[ring] + list(islands) for ring, islands in holes], COARSE_GRID,
                            1, enough, alone_search=False)
    rest = (~(depth >= enough)).ravel().nonzero()[0]
    if len(rest):
        x[rest], depth[rest] = deepest_points([holes[h] for h in rest], enough=enough)
    return x, depth


def _packed(polys):
    """The polygons of every hole (``polys[h]``: the ring, then its islands) packed:
    (edge starts a, ends b (e, 2), each hole's first edge and edge count, each
    edge's polygon within its hole (0: the ring), polygons per hole, each
    polygon's size)."""
    n_poly = np.fromiter(map(len, polys), np.int64, len(polys))
    flat = [p for ps in polys for p in ps]
    size = np.fromiter(map(len, flat), np.int64, len(flat))
    a = np.concatenate(flat)
    first = size.cumsum() - size
    nxt = np.arange(len(a)) + 1
    nxt[first + size - 1] = first
    hole_first = n_poly.cumsum() - n_poly
    e_count = np.add.reduceat(size, hole_first) if len(size) else np.zeros(0, np.int64)
    e_start = e_count.cumsum() - e_count
    poly_of_edge = (np.arange(len(flat)) - hole_first.repeat(n_poly)).repeat(size)
    return a, a[nxt], e_start, e_count, poly_of_edge, n_poly, size


def _search_many(polys, grid_n, rounds, enough, alone_search=True):
    """:func:`_search` of many holes (``polys[h]``: the ring, then its islands), the
    rounds of all holes together; (points (h, 2), depths (h,)).  ``alone_search``
    False: holes whose first round finds no candidate inside get none (depth
    -inf) instead of their own search."""
    n = len(polys)
    a, b, e_start, e_count, poly_of_edge, n_poly, size = _packed(polys)
    # each ring's box (the ring comes first among its hole's polygons)
    ring_size = size[n_poly.cumsum() - n_poly]
    bounds = columns(e_start, e_start + ring_size).ravel()
    padded = np.concatenate([a, a[:1]])
    lo = np.minimum.reduceat(padded, bounds)[::2]
    hi = np.maximum.reduceat(padded, bounds)[::2]
    center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    best, depth = center.copy(), np.full(n, -np.inf)
    unit = _unit_grid(grid_n)
    c = len(unit)
    active = np.ones(n, bool)
    alone = []
    for r in range(rounds):
        act = active.ravel().nonzero()[0]
        if not len(act):
            break
        cand = (center[act, None, :] + unit[None] * half[act, None, :]).reshape(-1, 2)
        hole = act.repeat(c)                       # the hole of each candidate
        inside = _inside_own(cand, hole, a, b, e_start, e_count, poly_of_edge, n_poly, grid_n)
        dist = _row_distance(cand, hole, inside, a, b, e_start, e_count, grid_n)
        dist = dist.reshape(len(act), c)
        any_in = inside.reshape(len(act), c).any(axis=1)
        if r == 0 and not any_in.all():
            if alone_search:
                alone += act[~any_in].tolist()         # thin holes: searched on their own
            active[act[~any_in]] = False
        i = np.argmax(dist, axis=1)
        di = dist[np.arange(len(act)), i]
        better = any_in & (di > depth[act])
        cand = cand.reshape(len(act), c, 2)
        up = act[better]
        best[up], depth[up] = cand[better, i[better]], di[better]
        go = act[active[act]]
        center[go], half[go] = best[go], half[go] * (4.0 / grid_n)
        stop = (np.hypot(half[go, 0], half[go, 1]) <= DEPTH_REL * depth[go]) | (depth[go] >= enough)
        active[go[stop]] = False
    for h in alone:
        best[h], depth[h] = _search(polys[h][0], polys[h][1:], grid_n, rounds, enough)
    return best, depth


def _pairs(owner, e_start, e_count):
    """(point, edge) index pairs of every point with every edge of its own hole
    (``owner[i]``: point i's hole; hole h's edges e_start[h] .. + e_count[h]),
    grouped by point, edges in order."""
    per = e_count[owner]
    pt = np.arange(len(owner)).repeat(per)
    off = np.arange(len(pt)) - (per.cumsum() - per).repeat(per)
    return pt, e_start[owner][pt] + off


def _inside_own(pts, owner, a, b, e_start, e_count, poly_of_edge, n_poly, row=1):
    """Whether each point is inside its hole's ring (odd winding) and inside none of
    its islands (even winding), as :func:`_search` tests with one winding number
    per polygon.  The points come in rows of ``row`` at one height (a search
    grid's rows): each row is paired with its hole's edges first, and only the
    edges spanning its height (the only ones :func:`morph.polyline.ray_crossings`
    can count) with the row's points."""
    rows = np.arange(0, len(pts), row)
    rp, e = _pairs(owner[rows], e_start, e_count)
    y = pts[rows[rp], 1]
    span = (a[e, 1] <= y) != (b[e, 1] <= y)
    rp, e = rp[span], e[span]
    pt = (rows[rp][:, None] + np.arange(row)).ravel()
    e = e.repeat(row)
    sign = pl.ray_crossings(pts[pt], a[e], b[e])
    hit = sign != 0
    pt, poly, sign = pt[hit], poly_of_edge[e[hit]], sign[hit]
    # winding number per (point, polygon) met: sums over the sorted keys
    key = pt * int(n_poly.max()) + poly
    order = np.argsort(key, kind="stable")
    key, sign = key[order], sign[order]
    first = np.concatenate([[True], key[1:] != key[:-1]]).ravel().nonzero()[0]
    odd = np.add.reduceat(sign, first) % 2 == 1 if len(key) else np.zeros(0, bool)
    kpt, kpoly = pt[order][first], poly[order][first]
    in_ring = np.zeros(len(pts), bool)
    in_ring[kpt[odd & (kpoly == 0)]] = True
    in_island = np.zeros(len(pts), bool)
    in_island[kpt[odd & (kpoly > 0)]] = True
    return in_ring & ~in_island


def _row_distance(pts, owner, inside, a, b, e_start, e_count, row):
    """Distance from each point ``inside`` to the nearest edge of its own hole's
    polygons (-inf for the others), the points in rows of ``row`` at one height.
    Exactly that minimum, on fewer pairs: a point's distance to the edges spanning
    its row's height bounds its minimum (an inside point has such an edge), and an
    edge farther in height from the row than the largest bound of the row's
    inside points cannot be nearest to any of them."""
    out = np.full(len(pts), -np.inf)
    if not inside.any():
        return out
    rows = np.arange(0, len(pts), row)
    rp, e = _pairs(owner[rows], e_start, e_count)
    y = pts[rows[rp], 1]
    lo_y, hi_y = np.minimum(a[e, 1], b[e, 1]), np.maximum(a[e, 1], b[e, 1])
    dy = np.maximum(np.maximum(lo_y - y, y - hi_y), 0.0)
    # bounds: distances to the spanning edges
    span = dy == 0.0
    pt = (rows[rp[span]][:, None] + np.arange(row)).ravel()
    es = e[span].repeat(row)
    keep = inside[pt]
    pt, es = pt[keep], es[keep]
    bound = np.full(len(pts), np.inf)
    np.minimum.at(bound, pt, pl.segment_distance(pts[pt], a[es], b[es]))
    row_bound = np.where(inside, bound, -np.inf).reshape(-1, row).max(axis=1)
    near = dy <= row_bound[rp]
    pt = (rows[rp[near]][:, None] + np.arange(row)).ravel()
    en = e[near].repeat(row)
    keep = inside[pt]
    pt, en = pt[keep], en[keep]
    d = pl.segment_distance(pts[pt], a[en], b[en])
    best = np.full(len(pts), np.inf)
    np.minimum.at(best, pt, d)
    out[inside] = best[inside]
    return out


def _own_distance(pts, owner, a, b, e_start, e_count):
    """Distance from each point to the nearest edge of its own hole's polygons."""
    pt, e = _pairs(owner, e_start, e_count)
    d = pl.segment_distance(pts[pt], a[e], b[e])
    return np.minimum.reduceat(d, e_count[owner].cumsum() - e_count[owner])


def _depths(x, polys):
    """:func:`_depth` of one point per hole (``polys[h]``: ring, then islands)."""
    a, b, e_start, e_count, poly_of_edge, n_poly, _ = _packed(polys)
    owner = np.arange(len(polys))
    inside = _inside_own(x, owner, a, b, e_start, e_count, poly_of_edge, n_poly)
    return np.where(inside, _own_distance(x, owner, a, b, e_start, e_count), -1.0)


def _depth(x, ring, islands):
    """Distance from x to the polygons' edges; -1 when x is not inside ring or is
    inside an island."""
    x = np.asarray(x, float)[None]
    if winding_number(x, [ring])[0] % 2 == 0 or any(winding_number(x, [i])[0] % 2 for i in islands):
        return -1.0
    polys = [ring] + list(islands)
    a = np.concatenate(polys)
    b = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    return float(min_segment_distance(x, a, b)[0])


@functools.lru_cache(maxsize=8)
def _unit_grid(grid_n):
    """The grid_n x grid_n points of [-1, 1]^2 that a search round tries, (grid_n^2, 2)
    (x fastest), made once per size (read-only)."""
    g = np.linspace(-1.0, 1.0, grid_n)
    unit = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    unit.flags.writeable = False
    return unit


def _search(ring, islands, grid_n, rounds, enough=np.inf):
    """:func:`deepest_point`'s grid search on the given polygons."""
    polys = [ring] + list(islands)
    a = np.concatenate(polys)
    b = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    lo, hi = ring.min(axis=0), ring.max(axis=0)
    center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    best, depth = center, -np.inf
    for r in range(rounds):
        cand = center + _unit_grid(grid_n) * half
        inside = winding_number(cand, [ring]) % 2 == 1
        for isl in islands:
            inside &= winding_number(cand, [isl]) % 2 == 0
        cand = cand[inside]
        if r == 0 and len(cand) == 0:
            # a thin hole slipped between the grid points: midpoints of its spans on
            # scanlines, the widest gaps between vertex heights first, then all
            cand = _span_midpoints(polys)
            if len(cand) == 0:
                cand = _span_midpoints(polys, lines=None)
        if len(cand):
            d = min_segment_distance(cand, a, b)
            i = int(np.argmax(d))
            if d[i] > depth:
                best, depth = cand[i], float(d[i])
        elif r == 0:
            return best, depth  # no area inside the hole: no point
        center, half = best, half * (4.0 / grid_n)
        if np.hypot(*half) <= DEPTH_REL * depth or depth >= enough:
            break  # a deeper point lies within the next cells: deeper by that at most
    return best, depth


def _span_midpoints(polys, lines=64):
    """Midpoints of the spans inside ``polys[0]`` and outside the islands
    ``polys[1:]`` (nested inside it, apart) on horizontal lines halfway between
    their vertices' heights, the widest gaps first, at most ``lines`` of them (None:
    all): with all lines, at least one lies inside a hole of positive area (its
    area lies between two consecutive heights somewhere, and the line halfway
    crosses it there)."""
    q = np.concatenate(polys)
    ys = unique(q[:, 1])
    if len(ys) < 2:
        return np.zeros((0, 2))
    gaps = np.diff(ys)
    pick = np.argsort(-gaps, kind="stable")
    pick = np.sort(pick if lines is None else pick[:lines])
    a = q
    b = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    out = []
    for ys_chunk in np.array_split(0.5 * (ys[pick] + ys[pick + 1]),
                                   max(1, len(pick) * len(q) // 2 ** 22 + 1)):
        y = ys_chunk
        hit = (a[None, :, 1] <= y[:, None]) != (b[None, :, 1] <= y[:, None])
        with np.errstate(divide="ignore", invalid="ignore"):
            x = a[None, :, 0] + (y[:, None] - a[None, :, 1]) * (b[None, :, 0] - a[None, :, 0]) / (
                b[None, :, 1] - a[None, :, 1])
        x = np.sort(np.where(hit, x, np.inf), axis=1)
        mid = 0.5 * (x[:, 0:-1:2] + x[:, 1::2])  # between crossings 1-2, 3-4, ...
        yy = np.broadcast_to(y[:, None], mid.shape)
        ok = np.isfinite(mid)
        out.append(np.stack([mid[ok], yy[ok]], axis=1))
    return np.concatenate(out)


class Membership:
    """x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅, for points at depth >= ``depth`` from the
    boundary candidates: A and B flattened within depth / 10 and intersected by
    Clipper on a grid of depth / 20 (finer for operands smaller than 1000 grid
    steps, so that neither collapses).  Loops of A with no area (paths traced
    forward and back, as strokes are) count as curves: open paths in Clipper.

    Most points of a hole are tested with no Clipper call: where the rounded loops
    of A and the rounded x − B are apart (:meth:`_apart`, exact integer
    predicates on the very polygons Clipper would get), Clipper's intersection is
    empty; only the other points go to Clipper.  A loop of A is flattened, rounded
    and measured when a point first needs it (its control box meets the box of
    x − B): the holes of a chunk of glyphs come near a fifth of its strokes."""

    def __init__(self, region_a, region_b, depth, areas=None, boxes=None):
        """``areas``: the loops' areas (:func:`morph.moments.loop_areas` of
        region_a) when known: the same for every depth; NaN where unknown (filled
        in as they are measured).  ``boxes``: :func:`control_boxes` of region_a
        when known."""
        self.flat = depth / 10.0
        self.region_a = region_a
        self.pb = pl.flatten_loops(region_b, self.flat)
        pts_b = np.concatenate(self.pb)
        sizes = np.fromiter(map(len, region_a), np.int64, len(region_a))
        self._ctrl = control_boxes(region_a) if boxes is None else boxes
        live = self._ctrl[sizes > 0]
        # the operands' extents: A's control boxes hold its loops
        size_a = float(max(live[:, 2].max() - live[:, 0].min(),
                           live[:, 3].max() - live[:, 1].min()))
        size = min(size_a, float(np.ptp(pts_b, axis=0).max()))
        self.grid = min(depth / 20.0, size / 1000.0)
        self._flat_area = 1e-9 * size * size
        self._areas = np.full(len(region_a), np.nan) if areas is None else areas
        self._sizes = sizes
        self.box_b = np.concatenate([pts_b.min(axis=0), pts_b.max(axis=0)])
        self._b_sizes = np.array([len(p) for p in self.pb], np.int64)
        self._pts_b = pts_b
        # per loop of A, once prepared (:meth:`_prepare`): its rounded points
        # (``_q[_first[k]:_first[k] + _count[k]]``; a path: its first half),
        # whether it is closed, whether Clipper takes it, its integer box
        n = len(region_a)
        self._ready = np.zeros(n, bool)
        self._q = np.zeros((0, 2), np.int64)
        self._first = np.zeros(n, np.int64)
        self._count = np.zeros(n, np.int64)
        self._closed = np.zeros(n, bool)
        self._ok = np.zeros(n, bool)
        self._box = np.zeros((n, 4), np.int64)
        self._lists = {}

    def _prepare(self, loops):
        """Flatten, round and measure the loops of A (indices) not done yet, all at
        once."""
        loops = loops[~self._ready[loops]]
        if not len(loops):
            return
        region = [self.region_a[k] for k in loops.tolist()]
        unknown = np.isnan(self._areas[loops])
        if unknown.any():
            self._areas[loops[unknown]] = mo.loop_areas([region[i] for i in
                                                         unknown.ravel().nonzero()[0].tolist()])
        sizes = self._sizes[loops]
        owner, _, pts = pl.flat_starts([p for loop in region for p in loop], self.flat)
        loop_of = np.arange(len(loops)).repeat(sizes)[owner]
        bounds = np.searchsorted(loop_of, np.arange(len(loops) + 1))
        n_pts = np.diff(bounds)
        closed = ~(np.abs(self._areas[loops]) <= self._flat_area)
        # a degenerate loop P, reverse(P): its first half (len(P) // 2 + 1 points, at
        # most all of them) is the path
        count = np.where(closed, n_pts, n_pts // 2 + 1)
        base = len(self._q)
        self._q = np.concatenate([self._q, self._int(pts)])
        self._first[loops] = base + bounds[:-1]
        self._count[loops] = count
        self._closed[loops] = closed
        self._ok[loops] = np.where(closed, n_pts >= 3, count >= 2)
        self._box[loops] = _boxes_of(self._q, base + bounds[:-1], np.maximum(count, 1))
        self._ready[loops] = True

    def _all(self):
        self._prepare(np.arange(len(self.region_a)))
        return self._closed.ravel().nonzero()[0], (~self._closed).ravel().nonzero()[0]

    @property
    def pa(self):
        """The closed loops of A, rounded: (m, 2) integer arrays."""
        return [self._part(k) for k in self._all()[0]]

    @property
    def curves(self):
        """The paths of A (loops with no area: their first half), rounded."""
        return [self._part(k) for k in self._all()[1]]

    @property
    def box_a(self):
        """The integer boxes (xmin, ymin, xmax, ymax) of :attr:`pa`."""
        return self._box[self._all()[0]]

    @property
    def box_c(self):
        """The integer boxes of :attr:`curves`."""
        return self._box[self._all()[1]]

    def _part(self, k):
        return self._q[self._first[k]:self._first[k] + self._count[k]]

    def _int(self, pts):
        return np.rint(pts / self.grid).astype(np.int64)

    def __call__(self, x):
        return bool(self.many(np.asarray(x, float)[None])[0])

    def many(self, points):
        """Membership of each of ``points`` (k, 2): the loops of A whose boxes meet
        the box of x - B found for all the points at once (control boxes first,
        then the rounded loops'); the points where they are apart from x - B
        (:meth:`_apart`, all at once) are outside; one Clipper intersection for
        each other point (each loop converted to Clipper's lists once)."""
        x = np.asarray(points, float).reshape(-1, 2)
        out = np.zeros(len(x), bool)
        if not len(x):
            return out
        lo = self._int(x - self.box_b[2:]) - 1
        hi = self._int(x - self.box_b[:2]) + 1
        # control boxes, on the grid and grown by a unit: they hold the rounded loops
        ctrl = np.concatenate([np.floor(self._ctrl[:, :2] / self.grid) - 1,
                               np.ceil(self._ctrl[:, 2:] / self.grid) + 1], axis=1)
        near, _ = _meeting_many(ctrl, lo.astype(float), hi.astype(float), self._sizes > 0)
        self._prepare(unique(near))
        part, first = _meeting_many(self._box, lo, hi, self._ok & self._ready)
        pt = np.arange(len(x)).repeat(np.diff(first))
        test = (np.diff(first) > 0).ravel().nonzero()[0]
        if not len(test):
            return out
        apart = self._apart(x, pt, part)
        first = first.tolist()
        for i in test[~apart[test]].tolist():
            ids = part[first[i]:first[i + 1]]
            out[i] = self._meets(x[i], ids[self._closed[ids]], ids[~self._closed[ids]])
        return out

    def _apart(self, x, pt, part):
        """Whether the rounded x − B of each point is apart from the rounded parts
        of A paired with it (``pt``, ``part``: the pairs, by point): no edge of one
        meets (touching counts) a segment of the other, a vertex of each part lies
        outside x − B, and a vertex of each loop of x − B outside the union of the
        closed parts (their winding numbers summed, the nonzero rule Clipper fills
        the subject with: a nib inside a counter of O is inside O's outer loop and
        outside O).  The boundaries meeting nowhere, each boundary loop
        (connected) lies on one side of the other operand, the side of its vertex:
        so apart means an empty intersection, a Clipper result with no area and no
        path, exactly.  All
        tests are on the integers Clipper gets (products below 2^63); only
        segments within the disc around x that holds x − B (plus two units:
        float distances, exact far beyond that) are tested against its edges.
        False for every point where the integers are too large for that."""
        n = len(x)
        used = unique(part)
        segs = self._segment_table(used)
        qb = np.rint((x[:, None, :] - self._pts_b[None]) / self.grid).astype(np.int64)
        if (max(int(np.abs(qb).max(initial=0)), int(np.abs(self._q).max(initial=0)))
                >= 2 ** 29):
            return np.zeros(n, bool)
        e0, e1, rep_b = self._edges_of_b(qb)
        centre = x / self.grid
        reach = np.sqrt(((e0 - centre[:, None]) ** 2).sum(axis=2)).max(axis=1,
                                                                       initial=0.0) + 2.0
        blocked = np.zeros(n, bool)
        # segments of the paired parts near the disc: contacts with x − B's edges
        at = np.searchsorted(used, part)
        s_first, s_count = segs["first"][at], segs["count"][at]
        sp = np.arange(len(part)).repeat(s_count)
        s = s_first.repeat(s_count) + _ranks(s_count)
        p_of = pt[sp]
        # the segments whose boxes come within reach first, then their distances
        c, r = centre[p_of], reach[p_of]
        lo_s, hi_s = segs["lo"][s], segs["hi"][s]
        box = np.all((lo_s - r[:, None] <= c) & (c <= hi_s + r[:, None]), axis=1)
        s, p_of, sp = s[box], p_of[box], sp[box]
        d = pl.segment_distance(centre[p_of], segs["a"][s].astype(float),
                                segs["b"][s].astype(float))
        near = d <= reach[p_of]
        s, p_of, sp = s[near], p_of[near], sp[near]
        m = e0.shape[1]
        if len(s) and m:
            si = s.repeat(m)
            pi = p_of.repeat(m)
            ei = np.tile(np.arange(m), len(s))
            touch = _segments_meet(segs["a"][si], segs["b"][si], e0[pi, ei], e1[pi, ei])
            blocked[pi[touch]] = True
        # a vertex of each part near the disc, outside x − B
        near_pair = unique(sp)
        if len(near_pair) and m:
            v = self._q[self._first[part[near_pair]]]
            blocked[pt[near_pair][_winding(v, pt[near_pair], e0, e1) != 0]] = True
        # a vertex of each loop of x − B outside each closed part
        blocked[self._inside_closed(pt, part, rep_b)] = True
        return ~blocked

    def _edges_of_b(self, qb):
        """x − B's edges (e0, e1: (n, m, 2)) over its loops of >= 3 points (those
        Clipper gets), cyclic, and a vertex of each such loop (n, loops, 2)."""
        b_first = self._b_sizes.cumsum() - self._b_sizes
        use = (self._b_sizes >= 3).repeat(self._b_sizes)
        nxt = np.arange(len(self._pts_b)) + 1
        nxt[b_first + self._b_sizes - 1] = b_first
        return qb[:, use], qb[:, nxt[use]], qb[:, b_first[self._b_sizes >= 3]]

    def _inside_closed(self, pt, part, rep_b):
        """The points (indices into ``pt``'s numbering) a vertex of whose x − B loop
        (``rep_b``) lies inside the closed parts paired with them: the winding
        numbers about all those parts summed (Clipper's nonzero rule on the
        subject), nonzero.  The vertex lies on no part's edge (the contact test
        comes first), so each winding number is exact."""
        closed_pair = self._closed[part].ravel().nonzero()[0]
        n_b = rep_b.shape[1]
        if not (len(closed_pair) and n_b):
            return np.zeros(0, np.int64)
        cp = closed_pair.repeat(n_b)
        j = np.tile(np.arange(n_b), len(closed_pair))   # the loop of x − B
        v = rep_b[pt[cp], j]
        k = part[cp]
        count = self._count[k]
        row = np.arange(len(cp)).repeat(count)
        e = self._first[k].repeat(count) + _ranks(count)
        e_next = np.where(_ranks(count) == count.repeat(count) - 1,
                          self._first[k].repeat(count), e + 1)
        # summed per (point, loop of x − B) over the point's closed parts
        key = (pt[cp] * n_b + j)[row]
        wind = np.bincount(key, weights=_crossing_signs(v[row], self._q[e], self._q[e_next]),
                           minlength=(int(pt.max()) + 1) * n_b)
        return unique((wind != 0).ravel().nonzero()[0] // n_b)

    def _segment_table(self, parts):
        """The segments of loops ``parts`` (ascending) as Clipper gets them: a
        closed loop's edges (with the closing one), a path's segments, a path on
        one grid point as a segment of one unit (:meth:`_meets`); {"a", "b": (s,
        2) ends, "first", "count": each part's}."""
        first, count, q = self._first[parts], self._count[parts], self._q
        closed = self._closed[parts]
        n_seg = np.where(closed, count, count - 1)
        i = first.repeat(n_seg) + _ranks(n_seg)
        last = (first + count - 1).repeat(n_seg)
        j = np.where(i == last, first.repeat(n_seg), i + 1)
        a, b = q[i], q[j]
        # a path whose points are all one grid point: a unit segment from it
        box = self._box[parts]
        dot = ~closed & np.all(box[:, :2] == box[:, 2:], axis=1)
        b = np.where(dot.repeat(n_seg)[:, None], a + np.array([1, 0]), b)
        return {"a": a, "b": b, "lo": np.minimum(a, b), "hi": np.maximum(a, b),
                "first": n_seg.cumsum() - n_seg, "count": n_seg}

    def _listed(self, k):
        if k not in self._lists:
            self._lists[k] = self._part(k).tolist()
        return self._lists[k]

    def _meets(self, x, closed_ids, curve_ids):
        """Whether A meets x - B, given the loops of A (indices into region_a, the
        closed ones and the paths) that can."""
        if not len(closed_ids) and not len(curve_ids):
            return False
        closed = [self._listed(k) for k in closed_ids]
        curves = [self._listed(k) for k in curve_ids]
        clip = pyclipper.Pyclipper()
        for c in closed:
            if not _add(clip, c, pyclipper.PT_SUBJECT, True):
                curves.append(c + c[:1])  # no area on the grid: its outline
        for c in curves:
            # a curve that rounds to one grid point: a segment of one unit (within
            # the flattening's depth / 10 of it)
            _add(clip, c, pyclipper.PT_SUBJECT, False) or _add(
                clip, [c[0], [c[0][0] + 1, c[0][1]]], pyclipper.PT_SUBJECT, False)
        moved = [self._int(x - p) for p in self.pb]
        if not any([_add(clip, p.tolist(), pyclipper.PT_CLIP, True) for p in moved if len(p) >= 3]):
            return False  # x - B rounds to no area
        tree = clip.Execute2(pyclipper.CT_INTERSECTION, pyclipper.PFT_NONZERO,
                             pyclipper.PFT_NONZERO)
        if pyclipper.OpenPathsFromPolyTree(tree):
            return True
        return any(abs(pyclipper.Area(p)) > 0 for p in pyclipper.ClosedPathsFromPolyTree(tree))


def control_boxes(region):
    """(k, 4) boxes (xmin, ymin, xmax, ymax) of the control points of each loop of
    ``region`` (zeros for an empty loop), all at once: each holds its loop."""
    sizes = np.fromiter(map(len, region), np.int64, len(region))
    out = np.zeros((len(region), 4))
    at = (sizes.cumsum() - sizes)[sizes > 0]
    if len(at):
        box = pc.bboxes([p for loop in region for p in loop])
        out[sizes > 0] = np.concatenate(
            [np.minimum.reduceat(box[:, :2], at), np.maximum.reduceat(box[:, 2:], at)], axis=1)
    return out


def _ranks(counts):
    """0 .. c - 1 for each count c, concatenated."""
    return np.arange(int(counts.sum())) - (counts.cumsum() - counts).repeat(counts)


def _orient(a, b, c):
    """The sign of (b − a) x (c − a), integer points (n, 2) each."""
    return np.sign((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                   - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def _segments_meet(a, b, c, d):
    """Whether closed integer segments ab and cd share a point (touching and
    overlapping count), exactly."""
    boxes = (np.all(np.minimum(a, b) <= np.maximum(c, d), axis=1)
             & np.all(np.minimum(c, d) <= np.maximum(a, b), axis=1))
    return (boxes & (_orient(a, b, c) * _orient(a, b, d) <= 0)
            & (_orient(c, d, a) * _orient(c, d, b) <= 0))


def _crossing_signs(v, a, b):
    """+1 / -1 where edge ab crosses the ray from v to the right upwards /
    downwards (half-open in y), else 0: their sum is the winding number of v, a
    point on no edge, exactly (integers)."""
    o = _orient(a, b, v)
    up = (a[:, 1] <= v[:, 1]) & (b[:, 1] > v[:, 1]) & (o > 0)
    down = (b[:, 1] <= v[:, 1]) & (a[:, 1] > v[:, 1]) & (o < 0)
    return up.astype(np.int64) - down


def _winding(v, row, e0, e1):
    """Winding numbers of points ``v`` (k, 2) about the edges e0[row[k]] ->
    e1[row[k]] ((n, m, 2) each)."""
    m = e0.shape[1]
    r = row.repeat(m)
    e = np.tile(np.arange(m), len(v))
    signs = _crossing_signs(v.repeat(m, axis=0), e0[r, e], e1[r, e])
    return signs.reshape(len(v), m).sum(axis=1)


def _add(clip, path, kind, closed):
    """Add one path to Clipper; False where Clipper refuses it (fewer than 2 distinct
    points, or a closed path with all its points on one line)."""
    try:
        return bool(clip.AddPath(path, kind, closed))
    except pyclipper.ClipperException:
        return False


def _boxes_of(q, first, count):
    """(k, 4) integer boxes (xmin, ymin, xmax, ymax) of the polygons
    q[first[k]:first[k] + count[k]] (count >= 1), all at once."""
    if not len(first):
        return np.zeros((0, 4), np.int64)
    idx = (first - count.cumsum() + count).repeat(count) + np.arange(count.sum())
    at = count.cumsum() - count
    rows = q[idx]
    return np.concatenate([np.minimum.reduceat(rows, at), np.maximum.reduceat(rows, at)], axis=1)


#: Query boxes times candidate boxes up to which :func:`_meeting_many` compares each
#: query with each candidate (four comparisons of (queries, candidates) planes)
#: instead of hashing all of them on a grid, whose cost is that of every candidate
#: box however few the queries: a chunk's hole test has the loops of every glyph
#: of the chunk as candidates, and the corner pass's few holes one query each.
MEETING_DIRECT = 1 << 15


def _meeting_direct(boxes, lo, hi, cand):
    """:func:`_meeting_many` of the candidates ``cand`` (ascending), every query
    box against every candidate: the same test on the same numbers, row-major, so
    each query's boxes come ascending."""
    b = boxes[cand]
    meet = ((b[:, 0] <= hi[:, 0, None]) & (b[:, 1] <= hi[:, 1, None])
            & (b[:, 2] >= lo[:, 0, None]) & (b[:, 3] >= lo[:, 1, None]))
    q, c = meet.nonzero()
    return cand[c], np.concatenate([[0], np.bincount(q, minlength=len(lo)).cumsum()])


def _meeting_many(boxes, lo, hi, ok):
    """For each box [lo[i], hi[i]], the ``ok`` boxes among ``boxes`` (k, 4) that
    meet it (touching counts), found through a grid of all the boxes
    (:func:`morph.polyline._cell_pairs`, a superset) and checked on the integers:
    (ids, first), box i's ascending in ids[first[i]:first[i + 1]]."""
    cand = ok.ravel().nonzero()[0]
    n = len(lo)
    if not len(cand) or not n:
        return np.zeros(0, np.int64), np.zeros(n + 1, np.int64)
    if n * len(cand) <= MEETING_DIRECT:
        return _meeting_direct(boxes, lo, hi, cand)
    pairs = _cell_pairs(BoxGrid(np.concatenate([lo, boxes[cand, :2]]).astype(float),
                                np.concatenate([hi, boxes[cand, 2:]]).astype(float)))
    i, j = pairs[:, 0], pairs[:, 1]
    cross = (i < n) & (j >= n)
    q, k = i[cross], cand[j[cross] - n]
    meet = (np.logical_and.reduce(boxes[k, :2] <= hi[q], axis=1)
            & np.logical_and.reduce(boxes[k, 2:] >= lo[q], axis=1))
    q, k = q[meet], k[meet]
    order = np.lexsort((k, q))
    return k[order], np.concatenate([[0], np.bincount(q, minlength=n).cumsum()])

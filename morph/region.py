"""Regions: lists of closed loops of rational pieces, oriented by nesting.

A *loop* is a list of pieces (``(n+1, 3)`` homogeneous arrays, see :mod:`morph.piece`)
whose joins are exact: the end of each piece equals the start of the next.  A *region*
is a list of loops; outer loops run counter-clockwise (positive area) and holes
clockwise, y axis up.  Loops of one region do not cross each other.

Everything here is a function on sequences of loops; :class:`Region` is the one
region type the package returns: its loops, whether they are validated, and the
error bound achieved.

Polyline work (winding numbers, point tests) uses :func:`morph.polyline.flatten`, whose
polylines lie within ``tol`` of the curves; a point closer than that to a boundary may
be classified either way.
"""

import numpy as np

from . import bernstein as bz
from . import moments as mo
from . import nearest as nr
from . import piece as pc
from . import polyline as pl
from .moments import region_centroid
from .polyline import (BoxGrid, distance_to_others, near_point_pairs, polyline_edges,
                       polylines_apart, polylines_touch, project, segment_distance, unique,
                       winding_number, winding_of_others)

__all__ = [
    "Region",
    "clean_loop",
    "is_zero_length",
    "without_zero_length",
    "zero_length_mask",
    "loop_bboxes",
    "loop_polyline",
    "orient_region",
    "orient_regions",
    "polyline_edges",
    "point_in_region",
    "region_bbox",
    "region_centroid",
    "region_polylines",
    "reverse_loop",
    "scale_region",
    "transform_region",
    "translate_region",
    "winding_number",
]

FILL_RULES = ("nonzero", "evenodd")


def _frozen(piece):
    """A read-only view of a piece as a float array (the caller's array stays as it was)."""
    a = np.asarray(piece, float)
    if a.flags.writeable:
        a = a.view()
        a.flags.writeable = False
    return a


class Region(tuple):
    """A region: a tuple of loops, each a tuple of read-only ``(n+1, 3)`` piece arrays,
    with what is known of it.

    - ``validated``: the loops are known to bound a region (winding number 1 inside,
      0 outside; outer loops counter-clockwise, holes clockwise): what
      :func:`orient_region`, :func:`morph.trim.fill_region` and the sums return.
      :func:`morph.minkowski.minkowski_sum` takes a validated operand without the
      winding test (:func:`morph.operands.winding_fault`, ~1-3 ms for a glyph); anything else is
      tested.
    - ``bound``: a certified bound of the Hausdorff distance between the loops and
      the exact shape they approximate (a sum's achieved error, at most its
      tolerance; what :meth:`morph.budget.Budget.after` takes), or None.

    A region cannot become invalid silently: it is immutable (its loops are tuples,
    its arrays read-only), and any change is a new object, which ``Region(loops)``
    makes unvalidated; :func:`translate_region` and :func:`transform_region` (by an
    invertible map) keep the mark.  It is a sequence of loops, so every function
    taking a list of loops takes it.
    """

    def __new__(cls, loops=(), bound=None):
        return cls._make(loops, False, bound)

    @classmethod
    def _make(cls, loops, validated, bound=None, frozen=False):
        """A region marked ``validated`` by the function that proved it (package use).
        ``frozen``: the caller made every piece a read-only float array already (rows
        of read-only stacks), so they are taken as they are, with no per-piece call."""
        obj = tuple.__new__(cls, map(tuple, loops) if frozen else
                            (tuple(map(_frozen, loop)) for loop in loops))
        object.__setattr__(obj, "validated", bool(validated))
        object.__setattr__(obj, "bound", None if bound is None else float(bound))
        return obj

    def __setattr__(self, name, value):
        raise AttributeError("a Region is immutable: make a new one")

    def __reduce__(self):
        return (Region._make, ([list(loop) for loop in self], self.validated, self.bound))

    @property
    def area(self):
        return mo.region_area(self)

    @property
    def bbox(self):
        return region_bbox(self)

    @property
    def centroid(self):
        return region_centroid(self)

    def contains(self, points, tol):
        return point_in_region(points, self, tol)

    def translated(self, offset):
        return translate_region(self, offset)

    def scaled(self, factor, center=(0.0, 0.0)):
        return scale_region(self, factor, center)

    def transformed(self, matrix):
        return transform_region(self, matrix)

    def __repr__(self):
        return "Region(%d loops, %d pieces%s%s)" % (
            len(self), sum(len(loop) for loop in self),
            ", validated" if self.validated else "",
            "" if self.bound is None else ", bound=%.3g" % self.bound)


def validated(loops, bound=None, frozen=False):
    """``loops`` as a validated :class:`Region` (package use: the caller has proved
    they bound a region, e.g. :func:`orient_region`; ``frozen``: as
    :meth:`Region._make`)."""
    return Region._make(loops, True, bound, frozen)


# ------------------------------------------------------------------ single loops

def is_zero_length(piece, rtol=1e-12):
    """True when all Cartesian control points of the piece coincide (up to rtol)."""
    return bool(zero_length_mask([piece], rtol)[0])


def zero_length_mask(pieces, rtol=1e-12):
    """:func:`is_zero_length` of many pieces (those of one degree at once): (k,) bools:
    all Cartesian control points within rtol max(1, max |coordinate|) of the first."""
    out = np.zeros(len(pieces), bool)
    for ks, h in pc.degree_groups(pieces):
        p = h[:, :, :2] / h[:, :, 2:]
        scale = np.maximum(1.0, np.abs(p).max(axis=(1, 2)))
        out[ks] = np.all(np.abs(p - p[:, :1]) <= rtol * scale[:, None, None], axis=(1, 2))
    return out


def without_zero_length(pieces):
    """The pieces that are not zero-length (:func:`zero_length_mask`), in order."""
    return [p for p, z in zip(pieces, zero_length_mask(pieces)) if not z]


def clean_loop(pieces, tol=None):
    """The loop with zero-length pieces dropped and every join snapped exactly.

    Each join (end of piece i, start of piece i+1, cyclically) is moved to the mean
    of the two end points, so afterwards ``piece.end(p[i]) == piece.start(p[i+1])``
    holds exactly.  With ``tol`` given, a gap larger than ``tol`` raises ValueError
    (the pieces do not form a closed loop).  Returns a new list; an empty list when
    nothing of positive length is left.
    """
    kept = without_zero_length([np.asarray(p, float) for p in pieces])
    if not kept:
        return []
    starts, ends = pc.end_points(kept)
    following = np.roll(starts, -1, axis=0)  # the start of piece i + 1, cyclically
    if tol is not None:
        gaps = np.hypot(*(ends - following).T)
        if (gaps > tol).any():
            i = int(np.argmax(gaps > tol))
            raise ValueError("loop is not closed: gap %.3g after piece %d exceeds tol %.3g"
                             % (gaps[i], i, tol))
    joins = 0.5 * (ends + following)
    before = np.roll(joins, 1, axis=0)
    return [pc.with_endpoints(p, before[i], joins[i]) for i, p in enumerate(kept)]


def reverse_loop(loop):
    """The same loop traversed the other way (pieces reversed, in reverse order)."""
    return [pc.reverse(p) for p in reversed(loop)]


def loop_polyline(loop, tol):
    """Closed polyline within ``tol`` of the loop, shape (m, 2), first point not repeated."""
    return pl.flatten_loop(loop, tol)


def region_polylines(loops, tol):
    """:func:`loop_polyline` of every loop, those with fewer than 3 points left out."""
    polys = [loop_polyline(loop, tol) for loop in loops]
    return [p for p in polys if len(p) >= 3]


def region_scale(loops):
    pts = [pc.cartesian(p) for loop in loops for p in loop]
    if not pts:
        return 1.0
    pts = np.concatenate(pts)
    ext = np.ptp(pts, axis=0)
    return float(max(ext.max(), 1e-300))


# ------------------------------------------------------------------ winding numbers

def sample_candidates(loop, max_candidates=32):
    """Points on the loop (piece mid-parameter points) used as nesting probes."""
    idx = np.linspace(0, len(loop) - 1, min(len(loop), max_candidates)).round().astype(int)
    return np.concatenate([pc.evaluate(loop[i], 0.5) for i in unique(idx)])


# ------------------------------------------------------------------ orientation

def orient_region(loops, fill_rule="nonzero", on_crossing=None):
    """Normalise loops to a region: outer loops counter-clockwise, holes clockwise.

    Input loops may have any orientation (TrueType outer contours are clockwise,
    CFF ones counter-clockwise, SVG either).  Zero-length pieces are dropped, joins
    snapped (:func:`clean_loop`), loops of zero area dropped (|area| <= 1e-12 of the
    loop's *own* extent squared and no self-crossing: tiny islands are kept, a bow
    tie whose lobes cancel is filled).  Coincident loops cancel as their windings do
    (:func:`_cancel_coincident`): opposite directions under either rule, equal
    directions under evenodd; equal directions under nonzero count once.  Then for
    each loop L
    a probe point on L is chosen (the piece midpoint farthest from the other
    loops' polylines) and ``w`` = the winding number there of all *other* loops
    (on polylines flattened to 1e-3 of the region's size, refined when a probe is
    closer than that).  Just outside L the winding number is ``w``, just inside
    ``w + s`` with s = +-1 the orientation of L.  The fill rule says which of the
    two sides is filled:

    - ``"nonzero"``: filled iff winding != 0.  Inside filled and outside empty: L is
      an outer boundary (made CCW); outside filled and inside empty: a hole (made
      CW); both filled: L is no boundary of the filled set and is dropped (e.g. a
      contour nested in another of the same direction).
    - ``"evenodd"``: filled iff the winding is odd; L is outer when ``w`` is even
      and a hole otherwise.

    Loops that cross or touch themselves or each other (overlapping font contours,
    self-intersecting SVG paths) are handed to ``on_crossing(loops, fill_rule)``,
    which cuts them at their intersections and fills them by the rule (the parsers
    pass :func:`morph.trim.fill_region`; this module does not depend on the
    trimming engine).  Returns a validated :class:`Region`.  Raises ValueError for an
    unknown fill rule, and for crossing loops when ``on_crossing`` is None.
    """
    if fill_rule not in FILL_RULES:
        raise ValueError("fill_rule must be one of %s, got %r" % (FILL_RULES, fill_rule))
    cleaned, areas = _positive_loops(loops)
    if not cleaned:
        return validated([])
    scale = region_scale(cleaned)
    cleaned, areas = _cancel_coincident(cleaned, areas, fill_rule, scale)
    if not cleaned:
        return validated([])
    polys = pl.flatten_loops(cleaned, APART * scale)   # shared by both tests below
    if loops_cross(cleaned, scale, polys):
        if on_crossing is None:
            raise ValueError("the loops cross or touch: they need a fill "
                             "(on_crossing=morph.trim.fill_region)")
        return validated(on_crossing(cleaned, fill_rule))
    if len(cleaned) == 1:
        return validated([cleaned[0] if areas[0] > 0 else reverse_loop(cleaned[0])])
    windings = outside_windings(cleaned, scale, polys)
    out = []
    for loop, area, w in zip(cleaned, areas, windings):
        is_outer = _is_outer(w, 1 if area > 0 else -1, fill_rule)
        if is_outer is not None:
            out.append(loop if (area > 0) == is_outer else reverse_loop(loop))
    return validated(out)


def orient_regions(regions, fill_rule="nonzero", on_crossing=None):
    """:func:`orient_region` of each of many regions (e.g. the glyphs of a chunk of a
    font): the same validated :class:`Region` each, to the bit, with the work of the
    common case done on arrays that hold the pieces of all of them.

    Every loop is cleaned (:func:`clean_loop`: zero-length pieces dropped, joins
    snapped), measured (extent, signed area) and flattened within APART x its
    region's size at once; the regions whose polylines are apart
    (:func:`morph.polyline.polylines_apart`, all regions in one grid) and whose
    loops all have an area and none a coincident twin (loop boxes and areas within
    1e-9 of the size, as :func:`_cancel_coincident` looks for them) are oriented by
    the winding numbers just outside their loops (:func:`outside_windings`, all
    probes at once).  The others (crossing or touching loops, a loop of no area,
    coincident loops: rare in fonts) go through :func:`orient_region` one by one.
    Raises as :func:`orient_region`.
    """
    if fill_rule not in FILL_RULES:
        raise ValueError("fill_rule must be one of %s, got %r" % (FILL_RULES, fill_rule))
    regions = list(regions)
    out = [None] * len(regions)
    b = _LoopBatch(regions)
    for g in b.slow:
        out[g] = orient_region(regions[g], fill_rule, on_crossing)
    for g in b.empty:
        out[g] = validated([])
    windings = b.outside_windings()
    for g in b.fast:
        loops = b.region_loops(g)
        if len(loops) == 1:
            k = loops[0]
            out[g] = validated([b.loop(k, b.kept_area[k] > 0)], frozen=True)
            continue
        kept = []
        for k in loops:
            positive = b.kept_area[k] > 0
            is_outer = _is_outer(int(windings[k]), 1 if positive else -1, fill_rule)
            if is_outer is not None:
                kept.append(b.loop(k, positive == is_outer))
        out[g] = validated(kept, frozen=True)
    return out


class _LoopBatch:
    """The loops of many regions cleaned, measured and flattened together, for
    :func:`orient_regions`: which regions take the common way (``fast``), which
    are left empty (``empty``) and which :func:`orient_region` handles (``slow``).

    The arithmetic is that of the one-region functions, element by element: the
    cleaned pieces (:func:`clean_loop`), each loop's extent (:func:`region_scale`)
    and signed area (:func:`morph.moments.loop_area`, summed by ``np.sum`` per loop),
    each region's size and polylines (:func:`morph.polyline.flatten_loops` within
    APART x the size): the same numbers, so the same decisions and pieces."""

    def __init__(self, regions):
        loops = [loop for region in regions for loop in region]
        self.nreg = len(regions)
        region_of = np.repeat(np.arange(len(regions)), [len(r) for r in regions])
        self._clean(loops)
        nonempty = self.sizes > 0
        self.lo, self.hi = self._extents()
        ext = np.maximum((self.hi - self.lo).max(axis=1), 1e-300)
        self.area = self._areas()
        positive = np.abs(self.area) > 1e-12 * ext * ext
        # a loop of (nearly) no area is kept only if it crosses itself: orient_region decides
        slow = np.zeros(len(regions), bool)
        slow[region_of[nonempty & ~positive]] = True
        kept = np.flatnonzero(nonempty & positive & ~slow[region_of])
        self.kept, self.region_of = kept, region_of[kept]
        self.kept_area = self.area[kept]
        count = np.bincount(self.region_of, minlength=len(regions))
        self.empty = np.flatnonzero((count == 0) & ~slow).tolist()
        lo, hi = pl.set_extents(self.lo[kept], self.hi[kept], self.region_of, len(regions))
        scale = np.ones(len(regions))
        has = count > 0
        scale[has] = np.maximum((hi[has] - lo[has]).max(axis=1), 1e-300)
        self.scale = scale
        slow |= self._coincident_candidates(count)
        sizes = self.sizes[kept]
        self.polys = pl.flatten_loop_pieces(
            self.stacked.take(np.repeat(self.first[kept], sizes) + _ranks_of(sizes)), sizes,
            APART * scale[self.region_of])
        slow |= ~self._apart()
        self.slow = np.flatnonzero(slow).tolist()
        self.fast = np.flatnonzero(has & ~slow).tolist()
        self._loops_of = np.split(np.arange(len(kept)),
                                  np.searchsorted(self.region_of, np.arange(1, len(regions))))

    # ----------------------------------------------------------------- cleaning

    def _clean(self, loops):
        """:func:`clean_loop` of every loop: ``pieces`` (the cleaned pieces, rows of
        per-degree stacks), ``sizes`` (pieces per loop) and ``first`` (index of each
        loop's first piece)."""
        # the pieces stacked once (one stack per degree), the kept ones taken from them
        pieces = pc.Pieces.of([p for loop in loops for p in loop])
        loop_of = np.repeat(np.arange(len(loops)), [len(loop) for loop in loops])
        keep = ~zero_length_mask(pieces) if len(pieces) else np.zeros(0, bool)
        idx = np.flatnonzero(keep)
        loop_of = loop_of[idx]
        self.sizes = np.bincount(loop_of, minlength=len(loops))
        self.first = np.cumsum(self.sizes) - self.sizes
        kept = pieces.take(idx)
        starts, ends = pc.end_points(kept)
        pos = np.arange(len(kept))
        last = self.first[loop_of] + self.sizes[loop_of] - 1
        following = np.where(pos == last, self.first[loop_of], pos + 1)
        joins = 0.5 * (ends + starts[following])
        preceding = np.where(pos == self.first[loop_of], last, pos - 1)
        before = joins[preceding]
        groups = []
        for ks, h in kept.groups:   # taken: a copy of its own
            h[:, 0, :2] = before[ks] * h[:, 0, 2:]
            h[:, -1, :2] = joins[ks] * h[:, -1, 2:]
            h.flags.writeable = False   # its rows are the regions' read-only pieces
            groups.append((ks, h))
        self.groups = groups
        self.stacked = pc.Pieces(groups, len(kept))
        self.pieces = self.stacked.rows()
        self._reversed = None
        self.loop_of = loop_of

    def loop(self, k, forward=True):
        """The cleaned pieces of kept loop ``k`` (an index into ``kept``), a list
        of read-only rows; ``forward`` False: :func:`reverse_loop` of it (the
        pieces of all loops reversed at once, on first use)."""
        j = int(self.kept[k])
        a, b = self.first[j], self.first[j] + self.sizes[j]
        if forward:
            return self.pieces[a:b]
        if self._reversed is None:
            flipped = []
            for ks, h in self.groups:
                r = h[:, ::-1].copy()
                r.flags.writeable = False
                flipped.append((ks, r))
            self._reversed = pc.Pieces(flipped, len(self.pieces)).rows()
        return self._reversed[a:b][::-1]

    def region_loops(self, g):
        """Indices (into ``kept``) of region g's kept loops, in order."""
        return self._loops_of[g].tolist()

    # ---------------------------------------------------------------- measures

    def _extents(self):
        """Lowest and highest control point (x, y) of each loop (inf / -inf for
        loops without pieces): :func:`region_scale` of one loop is the larger side."""
        n = len(self.sizes)
        lo = np.full((n, 2), np.inf)
        hi = np.full((n, 2), -np.inf)
        for ks, h in self.groups:
            c = h[:, :, :2] / h[:, :, 2:3]
            glo, ghi = pl.set_extents(c.min(axis=1), c.max(axis=1), self.loop_of[ks], n)
            np.minimum(lo, glo, out=lo)
            np.maximum(hi, ghi, out=hi)
        return lo, hi

    def _areas(self):
        """:func:`morph.moments.loop_area` of each loop (0 without pieces): the
        area terms of every piece about its loop's first point, summed by loop."""
        n = len(self.sizes)
        if not len(self.pieces):
            return np.zeros(n)
        origin = np.zeros((n, 2))
        has = self.sizes > 0
        origin[has] = pc.end_points(self.stacked.take(self.first[has]))[0]
        origin = origin[self.loop_of]
        moved = []
        for ks, h in self.groups:
            h = h.copy()
            h[:, :, :2] -= origin[ks][:, None] * h[:, :, 2:]
            moved.append((ks, h))
        terms = mo.area_terms(pc.Pieces(moved, len(self.pieces)))
        bounds = np.append(self.first, len(terms))
        return np.array([float(np.sum(terms[a:b])) if b > a else 0.0
                         for a, b in zip(bounds[:-1].tolist(), bounds[1:].tolist())])

    def _coincident_candidates(self, count):
        """Regions with a pair of kept loops that :func:`_cancel_coincident` would
        compare (tight boxes within 10 eps, |areas| within 1e-9 of each other, eps =
        1e-9 x the region's size): all pairs of loops of one region at once."""
        out = np.zeros(self.nreg, bool)
        many = count >= 2
        if not many.any():
            return out
        sel = np.flatnonzero(many[self.region_of])
        reg = self.region_of[sel]
        size = np.abs(self.kept_area[sel])
        end = np.searchsorted(reg, reg, side="right")
        cnt = end - np.arange(len(sel)) - 1
        i = np.repeat(np.arange(len(sel)), cnt)
        j = i + 1 + _ranks_of(cnt)
        # the areas first: the tight boxes (root finding) of the loops of such pairs only
        same = np.abs(size[i] - size[j]) <= 1e-9 * np.maximum(size[i], size[j])
        i, j = i[same], j[same]
        if not len(i):
            return out
        both = pl.unique(np.concatenate([i, j]))
        boxes = np.zeros((len(sel), 4))
        boxes[both] = loop_bboxes([self.loop(k) for k in sel[both].tolist()])
        eps = 1e-9 * self.scale[reg[i]]
        near = np.abs(boxes[i] - boxes[j]).max(axis=1) <= 10 * eps
        out[reg[i[near]]] = True
        return out

    def _apart(self):
        """:func:`morph.polyline.polylines_apart` of each region's polylines at tol =
        APART x its size (True for a region without loops)."""
        from .polyline import near_segment_pairs_grouped

        sizes = np.array([len(p) for p in self.polys], np.int64)
        a, b = polyline_edges(self.polys)
        edge_region = np.repeat(self.region_of, np.where(sizes >= 2, sizes, 0))
        tol = APART * self.scale
        near = near_segment_pairs_grouped(a, b, edge_region, 2.0 * tol)
        out = np.ones(self.nreg, bool)
        out[edge_region[near[:, 0]]] = False
        return out

    def outside_windings(self):
        """:func:`outside_windings` of the kept loops of the ``fast`` regions with two
        loops or more (others: 0), all probes at once: the same candidates (piece
        mid-points, :func:`sample_candidates`), distances and winding numbers, each
        region's loops counting only one another (:class:`morph.polyline.GroupGrid`)."""
        from .polyline import distance_to_others_grouped, winding_of_others_grouped

        out = np.zeros(len(self.kept), int)
        count = np.bincount(self.region_of, minlength=self.nreg)
        regions = [g for g in self.fast if count[g] >= 2]
        if not regions:
            return out
        loops = np.concatenate([self._loops_of[g] for g in regions])
        tol = APART * self.scale
        cand, owner = self._candidates(loops)
        # the polylines of these loops only (a region of one loop has no other to count)
        polys, group = [self.polys[k] for k in loops.tolist()], self.region_of[loops]
        mine = np.searchsorted(loops, owner)
        dist = distance_to_others_grouped(cand, mine, polys, group, 2 * tol)
        order = np.lexsort((dist, owner))  # per loop, its farthest candidate last
        best = order[np.searchsorted(owner[order], loops, side="right") - 1]
        out[loops] = winding_of_others_grouped(cand[best], np.arange(len(loops)), polys, group,
                                               self.nreg)
        region = self.region_of[loops]
        for i in np.flatnonzero(dist[best] < 2 * tol[region]).tolist():
            k, g = int(loops[i]), int(region[i])
            fine = max(0.25 * dist[best[i]], 1e-7 * self.scale[g])
            others = [loop_polyline(self.loop(j), fine) for j in self.region_loops(g) if j != k]
            out[k] = int(winding_number(cand[best[i]:best[i] + 1], others)[0])
        return out

    def _candidates(self, loops):
        """:func:`sample_candidates` of the kept loops ``loops`` (ascending): the
        points and the loop of each, in order.  The pieces are those of
        ``np.linspace(0, n - 1, min(n, 32)).round()`` (numpy's arithmetic), each
        evaluated at 1/2 as :func:`morph.piece.evaluate` does (the basis row times the
        control points, one matrix product per piece)."""
        n = self.sizes[self.kept[loops]]
        m = np.minimum(n, 32)
        owner = np.repeat(loops, m)
        i = _ranks_of(m)
        step = np.where(m > 1, (n - 1) / np.maximum(m - 1, 1), 0.0)
        idx = (i * step[np.repeat(np.arange(len(loops)), m)])
        idx[np.cumsum(m) - 1] = (n - 1)   # linspace ends at stop exactly
        idx = np.where(np.repeat(n <= 32, m), i, idx.round()).astype(np.int64)
        distinct = np.ones(len(idx), bool)
        distinct[1:] = (idx[1:] != idx[:-1]) | (owner[1:] != owner[:-1])
        owner, idx = owner[distinct], idx[distinct]
        piece = self.first[self.kept[owner]] + idx
        chosen = self.stacked.take(piece)
        pts = np.zeros((len(chosen), 2))
        for ks, h in chosen.groups:
            row = bz.basis(h.shape[1] - 1, [0.5])
            v = np.matmul(row, h)[:, 0]
            pts[ks] = v[:, :2] / v[:, 2:3]
        return pts, owner


def _ranks_of(counts):
    """0, 1, .., counts[0]-1, 0, 1, .., counts[1]-1, ..."""
    return np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)


def _positive_loops(loops):
    """Cleaned loops (:func:`clean_loop`) without those of zero area: |area| <= 1e-12
    of the loop's own extent squared and no self-crossing (tiny islands are kept, a
    bow tie whose lobes cancel is not dropped); and their signed areas."""
    out, areas = [], []
    for loop in loops:
        loop = clean_loop(loop)
        if not loop:
            continue
        ext = region_scale([loop])
        area = mo.loop_area(loop)
        if abs(area) > 1e-12 * ext * ext or loops_cross([loop], ext):
            out.append(loop)
            areas.append(area)
    return out, areas


def outside_windings(loops, scale, polys):
    """For each loop, the winding number just outside it: that of all *other* loops
    at a probe point on it (the piece midpoint farthest from the other loops, any
    of those farther than 2 tol = 2 APART x ``scale``), on their polylines ``polys``
    within tol, refined when the probe is closer than 2 tol.  All loops' probes at
    once (Python work per loop only for the rare refinements)."""
    tol = APART * scale
    cands = [sample_candidates(loop) for loop in loops]
    owner = np.repeat(np.arange(len(loops)), [len(c) for c in cands])
    cand = np.concatenate(cands)
    dist = distance_to_others(cand, owner, polys, 2 * tol)
    order = np.lexsort((dist, owner))  # per loop, its farthest candidate last
    best = order[np.searchsorted(owner[order], np.arange(len(loops)), side="right") - 1]
    out = winding_of_others(cand[best], np.arange(len(loops)), polys)
    for i in np.flatnonzero(dist[best] < 2 * tol):
        fine = max(0.25 * dist[best[i]], 1e-7 * scale)
        others = [loop_polyline(l, fine) for j, l in enumerate(loops) if j != i]
        out[i] = int(winding_number(cand[best[i]:best[i] + 1], others)[0])
    return [int(w) for w in out]


def _is_outer(w, s, fill_rule):
    """Is a loop of orientation ``s`` (+-1) with winding ``w`` just outside it an outer
    boundary (True), a hole (False) or no boundary of the filled set (None)?  Just
    inside, the winding is ``w + s``."""
    if fill_rule == "evenodd":
        return w % 2 == 0
    outside, inside = w != 0, (w + s) != 0
    return None if inside == outside else inside


def _cancel_coincident(loops, areas, fill_rule, scale):
    """Loops that trace the same curve (within 1e-9 of the size) reduced as their
    windings add up: a class of coincident loops whose directions sum to ``net``
    (+1 counter-clockwise, -1 clockwise) adds ``net`` times the class curve's
    winding number everywhere.  Evenodd keeps one loop of a class of odd size and
    none of an even one; nonzero keeps |net| / g loops in the direction of ``net``,
    g the greatest common divisor of all classes' |net| (nonzero fills where the
    total winding is not 0, which dividing every term by g does not change).  All
    exact: a class of n copies is one loop where the other classes' nets allow."""
    n = len(loops)
    if n < 2:
        return loops, areas
    rep = _coincident_classes(loops, areas, 1e-9 * scale, COINCIDENT_COARSE * scale)
    sign = np.where(np.asarray(areas, float) > 0, 1, -1)
    net = np.bincount(rep, weights=sign, minlength=n).astype(np.int64)
    size = np.bincount(rep, minlength=n)
    reps = np.flatnonzero(size)
    if fill_rule == "evenodd":
        copies = {r: (size[r] % 2, 1 if areas[r] > 0 else -1) for r in reps}
    else:
        g = np.gcd.reduce(np.abs(net[reps])) or 1
        copies = {r: (abs(net[r]) // g, 1 if net[r] > 0 else -1) for r in reps}
    out, out_areas = [], []
    for r in reps.tolist():
        count, direction = copies[r]
        loop = loops[r] if (areas[r] > 0) == (direction > 0) else reverse_loop(loops[r])
        out += [loop] * int(count)
        out_areas += [direction * abs(areas[r])] * int(count)
    return out, out_areas


def _coincident_classes(loops, areas, eps, coarse):
    """Class of each loop (the index of its first member): loops whose samples lie
    within 4 ``eps`` of each other's curves, both ways.  Candidates, all at once:
    tight bounding boxes (:func:`loop_bboxes`) within 10 eps (a grid search on the
    lower corners) and |areas| within 1e-9 of each other; each is compared with its
    class's first member (:class:`_LoopProbes`, polylines within ``coarse``)."""
    boxes = loop_bboxes(loops)
    size = np.abs(np.asarray(areas, float))
    pairs = near_point_pairs(boxes[:, :2], 10 * eps)
    i, j = pairs[:, 0], pairs[:, 1]
    keep = ((np.abs(boxes[i] - boxes[j]).max(axis=1) <= 10 * eps)
            & (np.abs(size[i] - size[j]) <= 1e-9 * np.maximum(size[i], size[j])))
    pairs = pairs[keep]
    pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
    rep = np.arange(len(loops))
    probes = _LoopProbes(loops, coarse)
    for i, j in pairs.tolist():
        if rep[i] == i and rep[j] == j and probes.on_loop(j, i, 4 * eps) \
                and probes.on_loop(i, j, 4 * eps):
            rep[j] = i
    return rep


#: Flattening bound (x the size) of the polylines that guide :class:`_LoopProbes` to
#: the pieces near a point: it bounds how far a candidate piece's polyline may be from
#: its nearest point, not the distance measured (Newton's foot on the piece).
COINCIDENT_COARSE = 1e-4


class _LoopProbes:
    """Distances from sample points of one loop to the curves of another, for many
    pairs of the same loops: each loop's samples (9 per piece) and tagged polyline
    (within ``coarse``) are made once, on first use."""

    def __init__(self, loops, coarse):
        self.loops, self.coarse = loops, float(coarse)
        self._samples, self._flat = {}, {}

    def samples(self, k):
        if k not in self._samples:
            t = np.linspace(0.0, 1.0, 9)
            self._samples[k] = np.concatenate([pc.evaluate(p, t) for p in self.loops[k]])
        return self._samples[k]

    def flat(self, k):
        """(stacked pieces, segment piece, t0, t1, a, b) of loop k's polyline."""
        if k not in self._flat:
            pieces = [np.asarray(p, float) for p in self.loops[k]]
            pid, ts, xy = pl.flat_starts(pieces, self.coarse)
            nxt = np.roll(np.arange(len(pid)), -1)
            t1 = np.where(pid[nxt] == pid, ts[nxt], 1.0)
            self._flat[k] = (pc.stack(pieces), pid, ts, t1, xy, xy[nxt])
        return self._flat[k]

    def on_loop(self, k, other, within):
        """Do all samples of loop k lie within ``within`` of loop ``other``'s curves?

        Each sample's distance is the least over Newton's feet on the pieces
        (:func:`morph.nearest.closest_params_many`), started from the projection on
        every polyline segment within ``within`` + 2 coarse of it: the segment
        whose parameter range holds a foot lies within coarse of the foot (the
        flattening bound), so a foot within ``within`` is reached from some start.
        """
        pts = self.samples(k)
        stacked, pid, t0, t1, a, b = self.flat(other)
        reach = within + 2.0 * self.coarse
        grid = BoxGrid(np.minimum(a, b) - reach, np.maximum(a, b) + reach)
        p, s = grid.at_points(pts)
        u = project(pts[p], a[s], b[s])
        near = segment_distance(pts[p], a[s], b[s]) <= reach
        p, s, u = p[near], s[near], u[near]
        if len(unique(p)) < len(pts):
            return False  # some sample is far from every segment
        start = t0[s] + u * (t1[s] - t0[s])
        foot = nr.closest_params_many(stacked[pid[s]], pts[p][:, None, :], start[:, None])
        q = pc.jet2_many(stacked[pid[s]], foot)[0][:, 0]
        best = np.full(len(pts), np.inf)
        np.minimum.at(best, p, np.hypot(*(q - pts[p]).T))
        return bool(best.max() <= within)


#: Loops whose arcs stay 2 APART x their size apart (polylines within APART x the size,
#: as :func:`morph.polyline.polylines_apart` tests) cross nowhere: only the others are
#: flattened within 1e-5 of the size to look for crossings (the test that most
#: glyphs pass cheaply).
APART = 1e-3


def loops_cross(loops, scale, polys=None):
    """True if the loops may cross or touch one another or themselves: their
    polylines within f = 1e-5 of the size come within 2 f of each other anywhere but
    between neighbouring edges (:func:`morph.polyline.polylines_touch`: a crossing
    at a joint, a vertex visited twice, collinear overlaps, a zero-width spike);
    False at once where their arcs are far apart (:func:`morph.polyline.polylines_apart`
    on the closed polylines ``polys`` within APART x ``scale``, made here when not
    given).  True is conservative: such loops are filled by the general trimming."""
    tol = APART * scale
    if polylines_apart(pl.flatten_loops(loops, tol) if polys is None else polys, tol):
        return False
    fine = 1e-5 * scale
    return polylines_touch(pl.flatten_loops(loops, fine), 2.0 * fine)


# ------------------------------------------------------------------ measures

def region_bbox(loops):
    """Tight bounding box (xmin, ymin, xmax, ymax) of all loops (see
    :func:`loop_bboxes`).  Raises ValueError for no pieces."""
    boxes = loop_bboxes(loops)
    if not len(boxes):
        raise ValueError("empty region has no bounding box")
    return np.concatenate([boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)])


def loop_bboxes(loops):
    """Tight bounding box (xmin, ymin, xmax, ymax) of each loop with pieces, (L, 4).

    Exact up to root finding: the extremes of each piece are at its ends or where a
    component of its tangent numerator vanishes (:func:`morph.piece.tangent_numerator_many`,
    roots by :func:`morph.bernstein.roots_many`), for all pieces of one degree and
    kind (polynomial or rational) at once.  Loops without pieces are left out.
    """
    pieces = [p for loop in loops for p in loop]
    if not pieces:
        return np.zeros((0, 4))
    loop_of = np.repeat(np.arange(len(loops)), [len(loop) for loop in loops])
    points, owners = [np.concatenate(pc.end_points(pieces))], [np.tile(loop_of, 2)]
    for ks, group, rational in pc.kind_groups(pieces):
        if group.shape[1] < 3:  # lines: their ends
            continue
        h = pc.tangent_numerator_many(group, rational)
        for axis in range(2):
            owner, t = bz.roots_many(h[:, :, axis])
            if len(t):
                points.append(pc.jet_rows(group[owner], t)[0])
                owners.append(loop_of[np.asarray(ks)[owner]])
    p, of = np.concatenate(points), np.concatenate(owners)
    n = len(loops)
    lo = np.full((n, 2), np.inf)
    hi = np.full((n, 2), -np.inf)
    np.minimum.at(lo, of, p)
    np.maximum.at(hi, of, p)
    used = np.bincount(loop_of, minlength=n) > 0
    return np.concatenate([lo, hi], axis=1)[used]


def point_in_region(points, loops, tol):
    """Boolean array: which points lie inside the region (nonzero winding).

    Loops are flattened within ``tol`` (absolute, region units); points within ``tol``
    of the boundary may go either way.  Vectorised over points and polyline edges.
    """
    polys = [loop_polyline(loop, tol) for loop in loops]
    return winding_number(points, polys) != 0


def translate_region(loops, offset):
    """All pieces moved by ``offset`` (dx, dy) (exact on homogeneous points); a
    :class:`Region` stays validated, with its bound."""
    out = [[pc.translate(p, offset) for p in loop] for loop in loops]
    if isinstance(loops, Region):
        return Region._make(out, loops.validated, loops.bound)
    return out


def scale_region(loops, factor, center=(0.0, 0.0)):
    """The region scaled by ``factor`` > 0 (a number, or (sx, sy)) about ``center``
    (exact on homogeneous points; a negative factor mirrors, see
    :func:`transform_region`)."""
    sx, sy = (factor, factor) if np.isscalar(factor) else factor
    cx, cy = center
    return transform_region(loops, [[sx, 0.0, cx - sx * cx], [0.0, sy, cy - sy * cy]])


def transform_region(loops, matrix):
    """All pieces mapped by the affine [[a, b, e], [c, d, f]] (exact on homogeneous points).

    A map with negative determinant reverses orientation; the loops are then reversed
    so that outer loops stay counter-clockwise.  A :class:`Region` stays validated
    under an invertible map, its bound scaled by the map's largest stretch.
    """
    m = np.asarray(matrix, float)
    out = [[pc.transform(p, m) for p in loop] for loop in loops]
    det = np.linalg.det(m[:2, :2])
    if det < 0:
        out = [reverse_loop(loop) for loop in out]
    if not isinstance(loops, Region):
        return out
    bound = None if loops.bound is None else loops.bound * np.linalg.norm(m[:2, :2], 2)
    return Region._make(out, loops.validated and det != 0, bound)

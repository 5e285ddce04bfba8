"""Topology from Clipper: the filled set of integer polylines under a fill rule.

Clipper (pyclipper, kept by the fontTools organisation) computes unions on integer
coordinates with exact predicates, so the planar subdivision is consistent every
time: no angle sorting, no float ties.  Collinear vertices are preserved, so every
input vertex on the boundary stays a vertex of the output, and every output edge
lies on one input segment (its ends are input vertices or crossings rounded to the
grid: within half a unit of both segments where they cross at an angle; Clipper
finds crossings in floating point, and those of nearly parallel segments came out
up to 10 units off on hanzi, which the lifting's Newton refinement absorbs).
Rings may touch themselves at a vertex (Clipper's StrictlySimple would split them,
at 20-30 times the cost): the lifting identifies every edge on its own, so it
does not need them apart.  Each group of paths apart from the others (a glyph of a
chunk, a stroke apart from the rest of its glyph) is united on its own, near the
origin (:func:`_union`).

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import gc
from contextlib import contextmanager
from dataclasses import dataclass
from itertools import chain

import numpy as np
import pyclipper

from ..polyline import BoxGrid, _cell_pairs, columns, member, unique

FILL_TYPES = {
    "positive": pyclipper.PFT_POSITIVE,
    "nonzero": pyclipper.PFT_NONZERO,
    "evenodd": pyclipper.PFT_EVENODD,
}


@dataclass
class Ring:
    """One boundary ring of the filled set: integer vertices (m, 2), filled side on
    its left (outer rings counter-clockwise, holes clockwise), ``parent`` the index
    of the ring that directly encloses it (-1 for none), ``group`` the apart group
    of paths it came from (:func:`_union`; -1 where not known)."""

    q: np.ndarray
    hole: bool
    parent: int
    group: int = -1


class Rings:
    """Boundary rings packed in arrays: ``sizes`` (k,), integer vertices ``q`` (n, 2)
    one ring after another, and per ring its ``hole`` flag, ``parent`` index (-1 for
    none; parents come before their children) and ``group`` (as :class:`Ring`'s).
    Trimming reads them as arrays: no object per ring."""

    __slots__ = ("sizes", "q", "hole", "parent", "group")

    def __init__(self, sizes, q, hole, parent, group):
        self.sizes, self.q, self.hole = sizes, q, hole
        self.parent, self.group = parent, group

    def __len__(self):
        return len(self.sizes)

    @property
    def starts(self):
        return self.sizes.cumsum() - self.sizes

    def rows(self, q=None):
        """Each ring's vertices (``q``: other values of the vertices, such as their
        float points), as a list of views."""
        q = self.q if q is None else q
        ends = self.sizes.cumsum().tolist()
        return [q[a:b] for a, b in zip([0] + ends[:-1], ends)]

    def kept(self, keep, parent):
        """The rings where mask ``keep`` holds, ``parent`` (k,) their parents before
        the renumbering (-1 or a ring left out: -1)."""
        index = keep.cumsum() - 1
        parent = np.where(parent >= 0, np.where(keep[parent], index[parent], -1), -1)
        return Rings(self.sizes[keep], self.q.compress(keep.repeat(self.sizes), axis=0),
                     self.hole[keep], parent[keep], self.group[keep])

    def to_list(self):
        """The rings as :class:`Ring` objects."""
        return [Ring(q, h, p, g) for q, h, p, g in zip(
            self.rows(), self.hole.tolist(), self.parent.tolist(), self.group.tolist())]

    @classmethod
    def of(cls, rings):
        """The :class:`Rings` of a list of :class:`Ring` (or a :class:`Rings`)."""
        if isinstance(rings, Rings):
            return rings
        if not rings:
            return _no_rings()
        return cls(np.array([len(r.q) for r in rings], np.int64),
                   np.concatenate([np.asarray(r.q, np.int64).reshape(-1, 2) for r in rings]),
                   np.array([r.hole for r in rings], bool),
                   np.array([r.parent for r in rings], np.int64),
                   np.array([r.group for r in rings], np.int64))


def _no_rings():
    z = np.zeros(0, np.int64)
    return Rings(z, np.zeros((0, 2), np.int64), z.astype(bool), z, z)


def filled_rings(paths, fill_rule, thin=0.0):
    """Boundary rings of the set filled by closed integer paths under ``fill_rule``
    ("positive": winding > 0, "nonzero", "evenodd"), nested by Clipper's PolyTree;
    rings of the union thinner than ``thin`` grid units (mean width, as in
    :func:`drop_slivers`) left out with everything inside them.

    Two passes: the union as flat rings first (:func:`_union`, on the paths'
    apart groups stacked in a column), then the PolyTree of those rings (which
    overlap nowhere; :func:`_nested_rings` in numpy where no ring visits a grid
    point twice).  Clipper 6 builds its tree while it joins edges, at a cost of
    (joins x rings x ring size): near-coincident input loops (many joins, many
    slivers) took minutes in one pass, and ~1 s in two.  Thin rings with no other
    ring inside go before the tree pass, where they would be most of its joins (3.4
    s of 3.7 s for three copies of a blob 1e-7 of its size apart).
    """
    paths = [np.asarray(p, np.int64).reshape(-1, 2) for p in paths]
    if not paths:
        return []
    return packed_filled_rings(np.array([len(p) for p in paths], np.int64),
                               np.concatenate(paths), fill_rule, thin).to_list()


def packed_filled_rings(sizes, q, fill_rule, thin=0.0, gap=None):
    """:func:`filled_rings` of paths packed as ``sizes`` (k,) and integer vertices
    ``q`` (n, 2), as :class:`Rings`; ``gap``: the grid units that part two apart
    groups of paths (:func:`_union`; at least APART_GAP): rings of two groups are
    farther apart than that."""
    keep = sizes >= 3
    if not keep.all():
        sizes, q = sizes[keep], q.compress(keep.repeat(sizes), axis=0)
    if not len(sizes):
        return _no_rings()
    sizes, q, group = _union(sizes, q, FILL_TYPES[fill_rule], max(gap or 0, APART_GAP))
    if not len(sizes):
        return _no_rings()
    if thin > 0.0:
        kept = _without_lone_slivers(thin, sizes, q)
        sizes, q, group = sizes[kept], q.compress(kept.repeat(sizes), axis=0), group[kept]
    if not len(sizes):
        return _no_rings()
    parts = _nested_parts(sizes, q, group)
    if parts is None:
        return _tree_pass(sizes, q)
    rings, unsure = parts
    if not unsure.any():
        return rings
    # the groups _nested_parts cannot nest: Clipper's tree pass on their rings alone
    # (a few strokes of a chunk, where the sweep over the whole chunk costs as much
    # as its union), after the others
    return _joined(rings, _tree_pass(sizes[unsure], q.compress(unsure.repeat(sizes), axis=0)))


def _tree_pass(sizes, q):
    """:class:`Rings` of Clipper's PolyTree of flat rings (``sizes``, ``q``), in the
    order of the tree walk (the last top-level ring first), groups unknown (-1)."""
    tree = _clipper(_packed_lists(sizes, q)).Execute2(
        pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    rings = []
    stack = [(child, -1) for child in tree.Childs]
    while stack:
        node, parent = stack.pop()
        rings.append(Ring(np.asarray(node.Contour, np.int64), bool(node.IsHole), parent))
        me = len(rings) - 1
        stack.extend((child, me) for child in node.Childs)
    return Rings.of(rings)


def _joined(first, then):
    """:class:`Rings` ``first``, then ``then`` (its parents renumbered after them)."""
    return Rings(np.concatenate([first.sizes, then.sizes]), np.concatenate([first.q, then.q]),
                 np.concatenate([first.hole, then.hole]),
                 np.concatenate([first.parent, np.where(then.parent >= 0,
                                                        then.parent + len(first), -1)]),
                 np.concatenate([first.group, then.group]))


#: Grid units between two groups of paths united apart: groups farther apart than
#: this (boxes grown by half of it do not meet) share no point of their union.
APART_GAP = 4


def _union(sizes, q, ft, gap=APART_GAP):
    """Clipper's union of closed integer paths (``sizes`` (k,), vertices ``q`` (n, 2))
    under fill type ``ft``, as flat rings (sizes, vertices, the group of paths each
    came from), in order of their top (largest y, then smallest x there) from the
    highest down.  Groups: boxes more than ``gap`` units apart.

    Clipper sweeps a horizontal line over the paths, and its work at each step
    grows with the edges the line crosses: a chunk of glyphs laid out in a grid
    puts a whole row of glyphs on every line (3 times the time of the glyphs on
    their own on hanzi).  So each group of paths apart from the others
    (:func:`_apart_groups`: the union of one shares no point with another's) is
    united on its own, moved by an integer offset to the origin (Clipper rounds
    the crossings of nearly parallel edges with an error that grows with the
    coordinates: smaller ones round them closer), and its rings moved back.  The
    order of the rings (Clipper's own depends on the layout) is that of their tops,
    a property of each ring alone."""
    starts = sizes.cumsum() - sizes
    lo, hi = np.minimum.reduceat(q, starts), np.maximum.reduceat(q, starts)
    group = _apart_groups(lo, hi, gap)
    g = int(group.max()) + 1
    glo = np.full((g, 2), np.iinfo(np.int64).max)
    ghi = np.full((g, 2), np.iinfo(np.int64).min)
    np.minimum.at(glo, group, lo)
    np.maximum.at(ghi, group, hi)
    shift = (glo + ghi) // 2
    # the paths in group order, each group's moved to the origin
    order = np.argsort(group, kind="stable")
    rows = starts[order].repeat(sizes[order]) + _ranks(sizes[order])
    moved = q.take(rows, axis=0) - shift.take(group[order], axis=0).repeat(sizes[order], axis=0)
    ends = np.bincount(group, minlength=g).cumsum().tolist()
    with _without_collection():
        lists = _packed_lists(sizes[order], moved)
        flat, ring_group = [], []
        for k, (a, b) in enumerate(zip([0] + ends[:-1], ends)):
            clip = _clipper(lists[a:b])
            rings = clip.Execute(pyclipper.CT_UNION, ft, ft) if clip else []
            flat += rings
            ring_group += [k] * len(rings)
        if not flat:
            return np.zeros(0, np.int64), np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
        f_sizes, f_q = _flat_arrays(flat)
    f_starts = f_sizes.cumsum() - f_sizes
    f_q += shift.take(ring_group, axis=0).repeat(f_sizes, axis=0)
    # each ring's top: its largest y, the smallest x at that height
    top_y = np.maximum.reduceat(f_q[:, 1], f_starts)
    at_top = f_q[:, 1] == top_y.repeat(f_sizes)
    top_x = np.minimum.reduceat(np.where(at_top, f_q[:, 0], np.iinfo(np.int64).max), f_starts)
    order = np.lexsort((top_x, -top_y))
    rows = f_starts[order].repeat(f_sizes[order]) + _ranks(f_sizes[order])
    return f_sizes[order], f_q.take(rows, axis=0), np.asarray(ring_group, np.int64)[order]


@contextmanager
def _without_collection():
    """Python's cyclic garbage collector off inside (and back on after, where it
    was on): Clipper's input and output are one small list or tuple per point, tens
    of thousands of allocations, each 700 of which start a collection that
    traverses the young objects (a quarter of the union's time on a hanzi chunk);
    they hold no cycles."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _ranks(counts):
    """0 .. c - 1 for each count c, concatenated."""
    return np.arange(int(counts.sum())) - (counts.cumsum() - counts).repeat(counts)


def _apart_groups(lo, hi, gap):
    """Group labels 0 .. g - 1 of boxes (lo, hi (k, 2) integer corners): the
    connected components of the boxes grown by ``gap`` / 2 that overlap, so boxes
    of two groups are more than ``gap`` apart in x or in y."""
    k = len(lo)
    label = np.arange(k)
    if k > 1:
        pairs = _cell_pairs(BoxGrid(lo - 0.5 * gap, hi + 0.5 * gap))
        if len(pairs):
            i, j = pairs[:, 0], pairs[:, 1]
            while True:  # each box takes the smallest label it is joined to
                m = np.minimum(label[i], label[j])
                new = label.copy()
                np.minimum.at(new, i, m)
                np.minimum.at(new, j, m)
                new = new[new]  # and its label's label
                if np.logical_and.reduce(new == label):   # np.array_equal: one shape
                    break
                label = new
    return np.searchsorted(unique(label), label)


def _flat_arrays(flat):
    """(sizes (k,), vertices (n, 2) int64) of Clipper's rings (lists of points)."""
    sizes = np.fromiter(map(len, flat), np.int64, len(flat))
    q = np.fromiter(chain.from_iterable(chain.from_iterable(flat)), np.int64,
                    2 * int(sizes.sum())).reshape(-1, 2)
    return sizes, q


def _nested_rings(flat, sizes=None, q=None, group=None):
    """The PolyTree of Clipper's flat rings (which overlap nowhere) without the tree
    pass (:func:`_nested_parts`), as :class:`Rings`; None where a ring cannot be
    nested so (then the tree pass decides).  ``sizes``, ``q``: :func:`_flat_arrays`
    of ``flat`` when known (then ``flat`` is not used); ``group``: each ring's group
    when known."""
    if q is None:
        sizes, q = _flat_arrays(flat)
    parts = _nested_parts(sizes, q, np.full(len(sizes), -1, np.int64) if group is None
                          else np.asarray(group, np.int64))
    if parts is None or parts[1].any():
        return None
    return parts[0]


def _nested_parts(sizes, q, group):
    """(the :class:`Rings` of the groups of flat rings whose PolyTree needs no tree
    pass, a mask of the rings of the other groups), or None where the coordinates
    are too large for exact winding numbers.

    A group needs the tree pass where one of its rings visits a grid point twice or
    shares one with another (the tree pass would split such rings apart), where
    the test point of a ring lies on another ring, or where a ring's orientation is
    not its depth's.  Elsewhere a ring's parent is the smallest ring (by area)
    around its first vertex: rings neither cross nor touch, so a ring lies inside
    another wherever one of its vertices does.  Winding numbers are exact on the
    integer vertices (products below 2^62).  Holes are the clockwise rings, which
    must be those at odd depth.  Rings come parents first, the last top-level ring
    first (the tree walk's order on Clipper's children).  Rings of two groups
    (``group`` (k,)) are apart: neither lies inside the other.
    """
    n = len(sizes)
    if not len(q) or int(np.abs(q).max()) >= 2 ** 30:
        return None
    lo_q, hi_q = q.min(axis=0), q.max(axis=0)
    height = int(hi_q[1] - lo_q[1]) + 1
    if (int(hi_q[0] - lo_q[0]) + 1) * height * len(q) >= 2 ** 62:
        return None
    unsure = np.zeros(n, bool)
    # every grid point once over all rings
    keys = (q[:, 0] - lo_q[0]) * height + (q[:, 1] - lo_q[1])
    if np.any(np.diff(np.sort(keys)) == 0):
        order = np.argsort(keys, kind="stable")
        twice = (np.diff(keys[order]) == 0).nonzero()[0]
        ring_of = np.arange(n).repeat(sizes)
        unsure[ring_of[order[twice]]] = unsure[ring_of[order[twice + 1]]] = True
    starts = sizes.cumsum() - sizes
    area, _ = packed_measures(sizes, q)
    a, b, on = _containers(q, sizes, starts)
    unsure[on] = True
    parent = np.full(n, -1, np.int64)
    if len(a):
        # the innermost container: the smallest by area
        order = np.lexsort((np.abs(area[b]), a))
        a, b = a[order], b[order]
        first = np.concatenate([[True], a[1:] != a[:-1]])
        parent[a[first]] = b[first]
    # depth by following parents (a chain of nested rings is short)
    depth = np.zeros(n, np.int64)
    up_ = parent.copy()
    while np.logical_or.reduce(up_ >= 0):
        depth += up_ >= 0
        up_ = np.where(up_ >= 0, parent[np.maximum(up_, 0)], -1)
    hole = area < 0
    unsure |= hole != (depth % 2 == 1)
    if unsure.any():   # every ring of an unsure ring's group
        unsure = member(group, unique(group[unsure]))
    rings = Rings(sizes, q, hole, parent, group)
    if unsure.any():
        rings, depth = rings.kept(~unsure, parent), depth[~unsure]
    return _tree_order(rings, depth), unsure


def _tree_order(rings, depth):
    """:class:`Rings` ``rings`` (their ``parent`` indices, ``depth`` the number of
    rings around each) in the order of a walk of the tree that takes the last
    top-level ring first and a ring's children after it, the last child first (the
    tree walk's order on Clipper's children), each naming its parent's new place.

    The walk's order is that of the rings' paths from the top (the ring indices of
    their ancestors, then their own), compared level by level with the larger index
    first and a path before those it begins: one sort of a (rings, depth + 1)
    table, filled by following the parents one level a round."""
    n = len(rings)
    levels = int(depth.max()) + 1 if n else 1
    path = np.full((n, levels), -n, np.int64)   # -n: below every -index, past the end
    row, at, d = np.arange(n), np.arange(n), depth.copy()
    for _ in range(levels):
        live = (d >= 0).nonzero()[0]
        path[row[live], d[live]] = -at[live]
        at = np.where(d > 0, rings.parent[np.maximum(at, 0)], -1)
        d = d - 1
    order = np.lexsort(path.T[::-1])
    place = np.empty(n, np.int64)
    place[order] = np.arange(n)
    parent = rings.parent[order]
    sizes = rings.sizes[order]
    rows = (rings.starts[order].repeat(sizes) + _ranks(sizes))
    return Rings(sizes, rings.q.take(rows, axis=0), rings.hole[order],
                 np.where(parent >= 0, place[np.maximum(parent, 0)], -1), rings.group[order])


def _containers(q, sizes, starts):
    """(a, b, on): the pairs of rings (``q`` their integer vertices, ``sizes``,
    ``starts``) where ring b winds around ring a's first vertex, and the rings of
    the pairs where that vertex lies on ring b (indices: the tree pass decides
    their nesting; their winding numbers are not used)."""
    lo = columns(np.minimum.reduceat(q[:, 0], starts), np.minimum.reduceat(q[:, 1], starts))
    hi = columns(np.maximum.reduceat(q[:, 0], starts), np.maximum.reduceat(q[:, 1], starts))
    # candidate (ring a, ring b around it): b's box holds a's
    first = q.take(starts, axis=0).astype(float)
    a, b = BoxGrid(lo.astype(float), hi.astype(float)).at_points(first)
    la, lb = lo.take(a, axis=0), lo.take(b, axis=0)
    ha, hb = hi.take(a, axis=0), hi.take(b, axis=0)
    keep = ((a != b) & (lb[:, 0] <= la[:, 0]) & (lb[:, 1] <= la[:, 1])
            & (hb[:, 0] >= ha[:, 0]) & (hb[:, 1] >= ha[:, 1]))
    a, b = a[keep], b[keep]
    on_rings = np.zeros(0, np.int64)
    if len(a):
        # winding number of a's first vertex about ring b: every edge of b
        per = sizes[b]
        pair = np.arange(len(a)).repeat(per)
        e = starts[b].repeat(per) + (np.arange(per.sum())
                                         - (per.cumsum() - per).repeat(per))
        last = (starts[b] + per - 1).repeat(per)
        e1 = np.where(e == last, starts[b].repeat(per), e + 1)
        p0, p1, v = q.take(e, axis=0), q.take(e1, axis=0), q.take(starts[a][pair], axis=0)
        cross = ((p1[:, 0] - p0[:, 0]) * (v[:, 1] - p0[:, 1])
                 - (p1[:, 1] - p0[:, 1]) * (v[:, 0] - p0[:, 0]))
        on = ((cross == 0) & (np.minimum(p0[:, 0], p1[:, 0]) <= v[:, 0])
              & (np.maximum(p0[:, 0], p1[:, 0]) >= v[:, 0])
              & (np.minimum(p0[:, 1], p1[:, 1]) <= v[:, 1])
              & (np.maximum(p0[:, 1], p1[:, 1]) >= v[:, 1]))
        on_pairs = pair[on]
        on_rings = np.concatenate([a[on_pairs], b[on_pairs]])
        up = (p0[:, 1] <= v[:, 1]) & (p1[:, 1] > v[:, 1]) & (cross > 0)
        down = (p1[:, 1] <= v[:, 1]) & (p0[:, 1] > v[:, 1]) & (cross < 0)
        wind = np.bincount(pair, weights=up.astype(float) - down, minlength=len(a))
        a, b = a[wind != 0], b[wind != 0]
    return a, b, on_rings


def _without_lone_slivers(thin, sizes, q):
    """Clipper's flat rings (``sizes``, integer vertices ``q``) without those thinner
    than ``thin`` units that hold no other ring (no ring's box inside theirs).  The
    flat rings wind once around what they fill, so without such a ring T the points
    inside T wind one less (T an outer ring: T empty) or one more (T a hole: T
    filled), and nothing else changes: the tree pass then gives what
    :func:`drop_slivers` leaves of the full tree.  A thin ring holding others stays
    for :func:`drop_slivers`, which drops what it holds with it.  Returns which
    rings are kept (a mask)."""
    starts = sizes.cumsum() - sizes
    area, perimeter = packed_measures(sizes, q)
    thin_ids = (2.0 * np.abs(area) <= thin * perimeter).ravel().nonzero()[0]
    if len(thin_ids) == 0:
        return np.ones(len(sizes), bool)
    qf = q.astype(float)
    lo = np.minimum.reduceat(qf, starts)
    hi = np.maximum.reduceat(qf, starts)
    p, b = BoxGrid(lo[thin_ids], hi[thin_ids]).at_points(qf[starts])
    t = thin_ids[b]
    lp, lt, hp, ht = lo[p], lo[t], hi[p], hi[t]
    holds = ((p != t) & (lp[:, 0] >= lt[:, 0]) & (lp[:, 1] >= lt[:, 1])
             & (hp[:, 0] <= ht[:, 0]) & (hp[:, 1] <= ht[:, 1]))
    drop = np.zeros(len(sizes), bool)
    drop[thin_ids] = True
    drop[t[holds]] = False
    return ~drop


def _as_lists(paths):
    """Integer paths as lists of (x, y) (pyclipper's input): the arrays among them
    converted in one call (:func:`_packed_lists`)."""
    if not paths or not all(hasattr(p, "tolist") for p in paths):
        return [p.tolist() if hasattr(p, "tolist") else p for p in paths]
    return _packed_lists(np.array([len(p) for p in paths], np.int64), np.concatenate(paths))


def _packed_lists(sizes, q):
    """Paths packed as ``sizes`` and vertices ``q`` as lists of (x, y): each
    coordinate column to a list and the two zipped (a third of the time of nested
    lists)."""
    flat = list(zip(q[:, 0].tolist(), q[:, 1].tolist()))
    ends = sizes.cumsum().tolist()
    return [flat[a:b] for a, b in zip([0] + ends[:-1], ends)]


def _clipper(paths):
    """A Pyclipper holding closed subject paths (collinear vertices kept), or None."""
    clip = pyclipper.Pyclipper()
    clip.PreserveCollinear = True
    try:
        clip.AddPaths(paths, pyclipper.PT_SUBJECT, True)
    except pyclipper.ClipperException:
        # Clipper refuses only when every path is invalid (all its points on one
        # line after the rounding): such paths enclose nothing
        return None
    return clip


def ring_area(q):
    """Signed area of an integer ring (shoelace; > 0 counter-clockwise)."""
    x, y = q[:, 0].astype(float), q[:, 1].astype(float)
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def ring_perimeter(q):
    d = np.diff(np.vstack([q, q[:1]]), axis=0).astype(float)
    return float(np.hypot(d[:, 0], d[:, 1]).sum())


def drop_slivers(rings, width):
    """Rings whose mean width 2·area/perimeter is below ``width`` grid units removed,
    with everything nested in them: near-coincident input edges rounded apart on the
    grid leave such slivers; a feature thinner than that merges with its side.
    ``rings``: :class:`Rings` (then so is the result), or a list of :class:`Ring`."""
    packed = Rings.of(rings)
    if not len(packed):
        return rings
    area, perimeter = packed_measures(packed.sizes, packed.q)
    dead = 2 * np.abs(area) <= width * perimeter
    up = packed.parent
    while True:   # a ring inside a dropped one goes too: one level of nesting a round
        inside = (up >= 0) & dead[np.maximum(up, 0)] & ~dead
        if not inside.any():
            break
        dead = dead | inside
    out = packed.kept(~dead, packed.parent)
    return out if isinstance(rings, Rings) else out.to_list()


def packed_measures(sizes, q):
    """(signed areas, perimeters) of rings packed as ``sizes`` (k,) and integer
    vertices ``q``, (k,) each, all at once (the areas exact: integer products and
    sums below 2^53)."""
    q = q.astype(float, copy=False)
    starts = sizes.cumsum() - sizes
    nxt = np.arange(len(q)) + 1
    nxt[starts + sizes - 1] = starts
    qn = q.take(nxt, axis=0)
    d = qn - q
    area = 0.5 * np.add.reduceat(q[:, 0] * qn[:, 1] - q[:, 1] * qn[:, 0], starts)
    perimeter = np.add.reduceat(np.hypot(d[:, 0], d[:, 1]), starts)
    return area, perimeter


def fill_holes(rings, filled):
    """Rings with the holes in ``filled`` (indices) closed: the hole ring goes, the
    islands inside it merge into the enclosing region (their holes stay).
    ``rings``: :class:`Rings` (then so is the result), or a list of :class:`Ring`."""
    packed = Rings.of(rings)
    closed = np.zeros(len(packed), bool)
    closed[np.asarray(filled, np.int64)] = True
    parent = packed.parent
    dead = closed | ((parent >= 0) & closed[np.maximum(parent, 0)] & ~packed.hole)
    while True:   # each ring's parent: the nearest ring around it that stays
        up = (parent >= 0) & dead[np.maximum(parent, 0)]
        if not up.any():
            break
        parent = np.where(up, packed.parent[np.maximum(parent, 0)], parent)
    out = packed.kept(~dead, parent)
    return out if isinstance(rings, Rings) else out.to_list()

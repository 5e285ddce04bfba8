"""Trimming closed loops of rational pieces to the boundary of what they fill (Sec. 6).

The paper's shape: a polygonal sweep on approximations decides the topology, then
the exact curves give the geometry.  Here:

1. :mod:`.flatten`: every piece flattened within ``eps`` (certified) where the
   topology is decided, and 32 times coarser along the simple arcs that nothing
   comes near (:func:`.flatten.adaptive_starts`), vertices
   snapped to an integer grid of unit ``grid`` and tagged (piece, t); segments
   routed through the hot pixels they cross (snap rounding: near-coincident
   segments keep their order).
2. :mod:`.topology`: Clipper's union under the fill rule ("positive" — winding > 0,
   the rule for oriented convolution loops — "nonzero" or "evenodd") on the
   integer polylines: a consistent planar subdivision every time, coincident
   pieces being ordinary overlaps.  Rings thinner than ``thin`` grid units on
   average (slivers between near-coincident pieces rounded apart) are dropped.
3. ``hole_test`` (for sums, :mod:`.holes`): every hole ring tested at an interior
   point with the exact membership predicate; filled holes are closed.
4. :mod:`.lift`: each ring's runs become the exact pieces restricted to their
   parameter ranges; crossings refined by Newton on the exact pieces.
5. :mod:`.untangle`: two outer loops whose exact pieces cross twice (two parts
   that overlap by less than a grid step, kept as two rings) are merged into their
   union (``merge_lenses``); where the exact pieces of a lifted loop still cross
   (twice within the polylines' error), the loop is split there and twisted or
   nested lobes go.

Error budget (each output point against the exact boundary of the filled set of
the input pieces): output pieces are sub-pieces of the input pieces; where the
topology is decided on the polylines it can be off by eps + grid/sqrt(2) (the
polyline and rounding errors), and junctions whose Newton iteration did not
converge sit on the grid point, within the same distance of both pieces.  Runs
shorter than ``contract`` are contracted, moving their neighbours' ends by less
than that.  Features thinner than 2 (eps + grid) may merge.  Loops may touch
themselves or each other at single points.
"""

import numpy as np

from ..polyline import (BoxGrid, _cell_pairs, near_segments, polylines_cross,
                        unique)
from ..region import validated
from .flatten import tag_loops
from .lift import lift_rings
from .topology import drop_slivers, fill_holes, packed_filled_rings
from .untangle import merge_lenses, untangle as untangle_loops

__all__ = ["boundary", "fill_region", "polylines_cross"]

THIN_UNITS = 1.5  # rings rounded apart by at most one grid step per vertex


def boundary(loops, eps, grid, fill_rule="positive", hole_test=None, contract=0.0,
             untangle=True, pieces=None, origin=None):
    """The region filled by closed ``loops`` of pieces under ``fill_rule``, as loops
    of rational pieces (outer counter-clockwise, holes clockwise).  ``pieces``: the
    loops' pieces one loop after another as a :class:`morph.piece.Pieces`, where the
    caller has them (:func:`morph.convolve.chain`).

    ``hole_test(ring, islands) -> bool`` (float polygons of a hole ring and of the
    rings directly inside it) says whether a hole is in fact filled.  See the
    module docstring for eps, grid, contract and the error budget.  ``origin``: a
    point of the integer grid (None: the middle of the loops' polylines' extent, as
    :func:`.flatten.tag_loops` takes it).
    """
    loops = [list(loop) for loop in loops if len(loop)]
    if not loops:
        return []
    tg = tag_loops(loops, eps, grid, origin, pieces=pieces)
    if len(tg.q) == 0:
        return []
    # each lifted loop lies within eps + grid + contract of its ring: loops whose
    # rings stay farther apart than twice that cannot cross; groups of paths united
    # apart (topology.packed_filled_rings) are farther apart than that
    reach = 2.0 * (eps + grid + contract)
    rings = drop_slivers(packed_filled_rings(np.diff(tg.starts), tg.q, fill_rule, THIN_UNITS,
                                             int(np.ceil(reach / grid)) + 1), THIN_UNITS)
    if hole_test is not None:
        rings = fill_holes(rings, _filled_holes(rings, tg, hole_test))
    out, of_ring, packed = lift_rings(rings, tg, contract, packed=True)
    of_ring = np.asarray(of_ring, np.int64)
    outer = ~rings.hole[of_ring]
    # the outer rings' vertices in one array, in the loops' order (a hole's ring counts
    # as empty)
    sizes = np.where(outer, rings.sizes[of_ring], 0)
    at = np.repeat(rings.starts[of_ring] - (sizes.cumsum() - sizes), sizes)
    pts = tg.to_float(rings.q[at + np.arange(len(at))])
    near = _near_ring_pairs(pts, sizes, reach, rings.group[of_ring])
    merged = merge_lenses(out, outer.tolist(), eps, near)
    if untangle:
        # each merge makes one loop of two: as many loops, none merged, the same pieces
        merged = untangle_loops(merged, eps, hole_test=hole_test,
                                pieces=packed if len(merged) == len(out) else None)
    return merged


def _filled_holes(rings, tg, hole_test):
    """Indices of the hole rings (of :class:`.topology.Rings` ``rings``) that
    ``hole_test`` finds filled: all holes in one call of its ``many`` method
    ([(ring, islands)] -> bools) where it has one, else one call per hole."""
    holes = rings.hole.nonzero()[0]
    if not len(holes):
        return []
    polygons = rings.rows(tg.to_float(rings.q))
    # each hole's islands: the rings whose parent it is, in ring order
    child = np.argsort(rings.parent, kind="stable")
    count = np.bincount(rings.parent + 1, minlength=len(rings) + 1)[1:]
    first = (count.cumsum() - count)[holes] + int(np.count_nonzero(rings.parent < 0))
    islands = [polygons[k] for k in child.tolist()]
    args = [(polygons[h], islands[a:b]) for h, a, b in zip(
        holes.tolist(), first.tolist(), (first + count[holes]).tolist())]
    many = getattr(hole_test, "many", None)
    filled = many(args) if many is not None else [hole_test(*a) for a in args]
    return holes[np.asarray(filled, bool)].tolist()


def _grown_boxes(pts, sizes, grow):
    """The boxes (lo, hi) of the polylines whose vertices are ``pts`` one polyline
    after another (``sizes`` their lengths, all positive), grown by ``grow``: all at
    once, (x, y) columns reduced at the polylines' starts."""
    at = sizes.cumsum() - sizes
    lo = np.stack([np.minimum.reduceat(pts[:, 0], at), np.minimum.reduceat(pts[:, 1], at)],
                  axis=1) - grow
    hi = np.stack([np.maximum.reduceat(pts[:, 0], at), np.maximum.reduceat(pts[:, 1], at)],
                  axis=1) + grow
    return lo, hi


def _edges_of(pts, sizes, sel):
    """The edges (a, b) of the closed polylines ``sel`` (a bool per polyline) among
    those whose vertices ``pts`` are stacked (``sizes`` each), as
    :func:`morph.polyline.polyline_edges` gives them."""
    a = pts[sel.repeat(sizes)]
    n = sizes[sel]
    last = n.cumsum() - 1
    following = np.arange(1, len(a) + 1)
    following[last] = last - n + 1   # each polyline closed: its last point to its first
    return a, a[following]


def _near_ring_pairs(pts, sizes, reach, group=None):
    """Index pairs (i < j) of closed polylines that come within ``reach`` of each
    other, the polylines' vertices ``pts`` one after another (``sizes`` each;
    polylines of fewer than 2 vertices are none's neighbours); ``group``: numbers
    such that polylines of two groups (both >= 0) are farther apart than ``reach``.

    Only edges that can be that near another polyline are compared: two edges
    within ``reach`` of each other have a midpoint within reach / 2 of both, in the
    boxes of their polylines grown by reach / 2 (so those boxes overlap) and in the
    edges' own boxes grown as much; so only the edges whose grown box meets the
    overlap of their polyline's grown box with another's go to
    :func:`morph.polyline.near_segments` (a chunk of a font is mostly glyphs apart
    from each other, and the rings of one glyph meet each other's boxes only in
    part).  All polylines at once."""
    use = sizes >= 2
    if np.count_nonzero(use) < 2:
        return set()
    pts, sizes = pts[use.repeat(sizes)], np.where(use, sizes, 0)
    has = sizes.ravel().nonzero()[0]
    half = 0.5 * reach
    lo, hi = _grown_boxes(pts, sizes[has], half)
    pairs = _cell_pairs(BoxGrid(lo, hi))
    if group is not None and len(pairs):
        g = group[has]
        gi, gj = g[pairs[:, 0]], g[pairs[:, 1]]
        pairs = pairs[(gi == gj) | (gi < 0) | (gj < 0)]
    if not len(pairs):
        return set()
    # the overlaps of the grown boxes, as (polyline, box) rows sorted by polyline
    ring = pairs.T.ravel()
    blo = np.tile(np.maximum(lo[pairs[:, 0]], lo[pairs[:, 1]]), (2, 1))
    bhi = np.tile(np.minimum(hi[pairs[:, 0]], hi[pairs[:, 1]]), (2, 1))
    order = np.argsort(ring, kind="stable")
    blo, bhi = blo[order], bhi[order]
    cnt = np.bincount(ring, minlength=len(has))
    first = cnt.cumsum() - cnt
    close = cnt.ravel().nonzero()[0]
    sel = np.zeros(len(sizes), bool)
    sel[has[close]] = True
    a, b = _edges_of(pts, sizes, sel)
    owner = close.repeat(sizes[has[close]])               # index into has
    per = cnt[owner]
    e = np.arange(len(a)).repeat(per)
    box = first[owner][e] + (np.arange(len(e)) - (per.cumsum() - per).repeat(per))
    elo, ehi = np.minimum(a, b)[e] - half, np.maximum(a, b)[e] + half
    bh, bl = bhi[box], blo[box]
    meets = ((elo[:, 0] <= bh[:, 0]) & (elo[:, 1] <= bh[:, 1])
             & (ehi[:, 0] >= bl[:, 0]) & (ehi[:, 1] >= bl[:, 1]))
    keep = np.zeros(len(a), bool)
    keep[e[meets]] = True
    if not keep.any():
        return set()
    a, b, owner = a[keep], b[keep], has[owner[keep]]
    found = near_segments(a, b, reach)
    if not len(found):
        return set()
    i, j = owner[found[:, 0]], owner[found[:, 1]]
    keep = i != j
    return set(zip(np.minimum(i, j)[keep].tolist(), np.maximum(i, j)[keep].tolist()))


def fill_region(loops, fill_rule="nonzero", rel=1e-7):
    """The region filled by closed loops that may cross themselves and each other.

    SVG and font fill semantics: a point is filled when the winding number of all
    loops there is nonzero (``"nonzero"``) or odd (``"evenodd"``).  The boundary is
    made of sub-pieces of the input (rational Béziers): outer loops
    counter-clockwise, holes clockwise.  Topology is decided on polylines within
    ``rel`` times the loops' size, on a grid of that size (:func:`boundary`), for
    each group of loops whose boxes stay apart at its own size (:func:`_apart_groups`:
    a tiny island is kept); pieces folded within that resolution are unfolded
    (:func:`unfold_flat_curl`) and holes thinner than it dropped
    (:func:`_without_sliver_holes`), so that a curl is filled as a renderer fills it.
    Returns a validated :class:`morph.region.Region`.
    """
    if fill_rule not in ("nonzero", "evenodd"):
        raise ValueError("fill_rule must be 'nonzero' or 'evenodd', got %r" % (fill_rule,))
    loops = [loop for loop in loops if len(loop)]
    if not loops:
        return validated([])
    groups = _apart_groups(loops, rel * _size(loops))
    return validated([loop for group in groups
                      for loop in _fill_group([loops[k] for k in group], fill_rule, rel)])


def _points(piece):
    h = np.asarray(piece, float)
    return h[:, :2] / h[:, 2:]


def _size(loops):
    """The larger side of the loops' control-point box."""
    pts = np.concatenate([_points(p) for loop in loops for p in loop])
    return max(float(np.ptp(pts, axis=0).max()), 1e-300)


def _fill_group(loops, fill_rule, rel):
    """:func:`fill_region` of loops that are not apart, at ``rel`` times their size."""
    eps = rel * _size(loops)
    loops = [[unfold_flat_curl(p, eps) for p in loop] for loop in loops]
    return _without_sliver_holes(boundary(loops, eps, eps, fill_rule), eps)


def _apart_groups(loops, margin):
    """The loops in groups (lists of indices, in order of their first loop) whose
    control-point boxes, grown by ``margin``, overlap within a group and not
    between groups: the groups neither cross nor nest nor touch, so each is filled
    on its own, at its own size.  A tiny island beside a large shape is then
    resolved at its size, not dropped as a sliver of the whole's grid: an island is
    small only until something is added to it."""
    pts = [np.concatenate([_points(p) for p in loop]) for loop in loops]
    boxes = np.array([[*(c.min(axis=0) - margin), *(c.max(axis=0) + margin)] for c in pts])
    meets = ((boxes[:, None, 0] <= boxes[None, :, 2]) & (boxes[None, :, 0] <= boxes[:, None, 2])
             & (boxes[:, None, 1] <= boxes[None, :, 3]) & (boxes[None, :, 1] <= boxes[:, None, 3]))
    group = np.arange(len(loops))
    changed = True
    while changed:  # each loop takes the smallest group index it meets, to a fixed point
        new = np.min(np.where(meets, group[None, :], len(loops)), axis=1)
        changed = bool(np.any(new != group))
        group = new
    return [list((group == g).ravel().nonzero()[0]) for g in unique(group)]


def _without_sliver_holes(loops, eps):
    """The loops without holes thinner than ``eps`` on average (2 |area| / length):
    the lobe of a curl that a glyph's contour draws just inside itself, lifted from
    a ring of the polylines within ``eps`` as exact pieces a hundredth as wide.  A
    hole that thin is below the fill's resolution (features thinner than 2 eps may
    merge with their side, :func:`boundary`) and no renderer shows it; the sums
    would take its convolution for a bite.  Islands, however small, are kept."""
    from .. import moments as mo
    from .. import polyline as pl

    out = []
    for loop in loops:
        area = mo.loop_area(loop)
        if area < 0:
            flat = np.concatenate([f[0] for f in pl.flatten_many(loop, eps)])
            length = float(np.sum(np.hypot(*np.diff(flat, axis=0).T)))
            if 2.0 * -area < eps * length:
                continue
        out.append(loop)
    return out


def unfold_flat_curl(piece, eps):
    """A piece that folds back on itself within ``eps`` of its chord, replaced by the
    chord (a line); any other piece as it is.

    Such a piece is a curl thinner than the fill resolves (a handwriting font's
    pen reversal whose lobe is 1e-8 of its length wide): the fill decides topology
    on polylines within ``eps``, where the curl is its chord folded onto itself, and
    a renderer fills nothing of its lobe; but the lifted exact piece would keep the
    curl, whose tangent turns a full turn more than the loop's, which no sum takes.
    Every point of the curve is within ``eps`` of the chord (its control points are:
    the convex hull), and it runs within the chord's ends (its polyline within
    ``eps / 4`` does, within ``eps``), so the two are within ``eps`` of each other
    (Hausdorff): the fill's own error.
    """
    h = np.asarray(piece, float)
    if len(h) < 3:
        return piece
    c = h[:, :2] / h[:, 2:]
    a, b = c[0], c[-1]
    length = float(np.hypot(*(b - a)))
    if length <= eps:
        return piece
    d = (b - a) / length
    rel = c - a
    if np.max(np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0])) > eps:
        return piece
    from .. import piece as pc
    from .. import polyline as pl

    along = (pl.flatten(h, eps / 4.0)[0] - a) @ d
    if np.all(np.diff(along) >= 0) or along.min() < -eps or along.max() > length + eps:
        return piece  # no fold, or one reaching past the chord's ends (a spike)
    return pc.line(a, b)

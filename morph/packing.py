"""Several regions laid side by side, so that one computation serves them all.

Every phase of a Minkowski sum (Gauss maps, convolution, flattening, Clipper,
lifting) costs a few array calls however many pieces it gets, so the sums of many
regions with one common operand (a font's glyphs with one nib) cost far less as one
sum of all the regions moved apart than as one sum each: ``(A + t) ⊕ B = (A ⊕ B) + t``,
and sums of regions whose slots are far enough apart cannot meet.  A
:class:`Packing` moves the regions into the cells of a square grid (translation of
homogeneous points: exact up to the rounding of coordinates a few cells from the
origin, which every decision of the sum must tolerate anyway; see
``tests/test_stroke.py``'s sums far from the origin), tells which slot a point is in,
and splits a result by slot and moves it back.
"""

from itertools import chain

import numpy as np

from . import piece as pc


def control_box(region):
    """(xmin, ymin, xmax, ymax) of a region's control points: a box holding every
    piece (positive weights: the convex-hull property)."""
    boxes = pc.bboxes([p for loop in region for p in loop])
    return np.concatenate([boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)])


class Packing:
    """Regions moved to the cells of a square grid, for results that lie within
    their region's box plus the box ``reach`` (x0, y0, x1, y1): for A ⊕ B, the box
    of B's control points.

    Each cell is wider and taller than the largest region by ``reach``'s size plus
    ``margin`` (a number or (x, y)).  ``offsets[i]`` is the translation of region i;
    ``packed`` all their loops, in order; ``slot_boxes[i]`` the box of region i
    moved, plus ``reach``, widened by ``margin`` / 4 on every side: the slot boxes
    are ``margin`` / 2 apart, and the moved regions ``reach``'s size plus ``margin``.
    ``pieces``: the regions' pieces in order as a :class:`morph.piece.Pieces`, when
    the caller has them stacked (None: stacked here, once for the boxes and the
    moves); ``self.pieces`` is the moved pieces' (``packed``'s) stacks, for the
    functions that take the packed region's pieces stacked.  ``step``: every offset
    is a whole multiple of it (rounded to the nearest, which moves a region by at
    most ``step`` / 2 in its cell: ``margin`` must exceed 2 ``step``), so that a grid
    of that unit anchored at the origin falls on each region as it does unmoved.
    """

    def __init__(self, regions, reach, margin, pieces=None, step=None):
        if pieces is None:
            pieces = pc.Pieces.of([p for r in regions for loop in r for p in loop])
        boxes = _control_boxes(regions, pieces)
        reach = np.asarray(reach, float)
        margin = np.broadcast_to(np.asarray(margin, float), (2,))
        pitch = (boxes[:, 2:] - boxes[:, :2]).max(axis=0) + (reach[2:] - reach[:2]) + margin
        cols = int(np.ceil(np.sqrt(len(regions))))
        cell = np.stack([np.arange(len(regions)) % cols, np.arange(len(regions)) // cols], 1)
        corner = cell * pitch - 0.5 * pitch * [cols, -(-len(regions) // cols)]
        self.offsets = corner - boxes[:, :2]
        start = corner[0] + reach[:2] - 0.25 * margin  # where grid cell 0 begins
        if step is not None:
            self.offsets = step * np.rint(self.offsets / step)
            corner = self.offsets + boxes[:, :2]
        self.packed, self.pieces = _translated(
            [loop for r in regions for loop in r],
            np.repeat(self.offsets, [len(r) for r in regions], axis=0), pieces=pieces,
            stacks=True)
        lo, hi = corner + reach[:2] - 0.25 * margin, boxes[:, 2:] + self.offsets + reach[2:]
        self.slot_boxes = np.concatenate([lo, hi + 0.25 * margin], axis=1)
        self.pitch, self.cols = pitch, cols
        self.origin = start  # slot box i begins in grid cell i (where it does, without step)

    def slot_of(self, points):
        """Slot of each point (m, 2) (-1 for a point in no slot's box).  Slot box i
        begins where its grid cell does, so the cell says which box to test."""
        points = np.asarray(points, float).reshape(-1, 2)
        cell = np.floor((points - self.origin) / self.pitch).astype(np.int64)
        idx = cell[:, 1] * self.cols + cell[:, 0]
        ok = (cell[:, 0] >= 0) & (cell[:, 0] < self.cols) & (idx >= 0) & (idx < len(self.offsets))
        b = self.slot_boxes[np.where(ok, idx, 0)]
        ok &= np.all((b[:, :2] <= points) & (points <= b[:, 2:]), axis=1)
        return np.where(ok, idx, -1)

    def split(self, loops):
        """Loops (of pieces, in packed coordinates) sorted into one list per region by
        the slot of their first point, moved back; the pieces are read-only rows of
        new stacks (what :func:`morph.region.validated` takes as ``frozen``).  Raises
        ValueError for a loop in no slot."""
        out = [[] for _ in self.offsets]
        if not loops:
            return out
        slots = self.slot_of(pc.end_points([loop[0] for loop in loops])[0])
        if (slots < 0).any():
            raise ValueError("a loop of the packed result lies outside every slot")
        for loop, s in zip(_translated(loops, -self.offsets[slots], frozen=True),
                           slots.tolist()):
            out[s].append(loop)
        return out


def _control_boxes(regions, pieces=None):
    """:func:`control_box` of each region, (n, 4): the boxes of all their pieces in
    one call, reduced per region (``pieces``: theirs stacked, as :class:`Packing`
    takes them)."""
    sizes = [sum(map(len, r)) for r in regions]
    if pieces is None:
        pieces = list(chain.from_iterable(chain.from_iterable(regions)))
    boxes = pc.bboxes(pieces)
    start = np.cumsum([0] + sizes[:-1])
    return np.concatenate([np.minimum.reduceat(boxes[:, :2], start, axis=0),
                           np.maximum.reduceat(boxes[:, 2:], start, axis=0)], axis=1)


def _translated(loops, offsets, frozen=False, pieces=None, stacks=False):
    """Each loop moved by its offset (:func:`morph.piece.translate`, exact on
    homogeneous points), the pieces of one degree at once (``frozen``: the new
    stacks made read-only, so their rows are).  ``pieces``: the loops' pieces
    stacked (a :class:`morph.piece.Pieces`; None: stacked here).  With ``stacks``,
    (loops, the moved pieces as a :class:`morph.piece.Pieces`)."""
    sizes = [len(loop) for loop in loops]
    if pieces is None:
        pieces = list(chain.from_iterable(loops))
    shift = np.repeat(np.asarray(offsets, float).reshape(-1, 2), sizes, axis=0)
    groups = []
    for ks, h in pc.degree_groups(pieces):
        h = h.copy()
        h[..., :2] += shift[ks][:, None] * h[..., 2:]
        h.flags.writeable = not frozen
        groups.append((ks, h))
    table = pc.Pieces(groups, len(pieces))
    moved = table.rows()
    bounds = np.cumsum([0] + sizes).tolist()
    out = [moved[a:b] for a, b in zip(bounds[:-1], bounds[1:])]
    return (out, table) if stacks else out


__all__ = ["Packing", "control_box"]

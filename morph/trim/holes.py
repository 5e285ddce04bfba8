"""Holes of the winding-number result, decided by the exact membership predicate.

Winding numbers of the convolution curve are positive exactly on points of A ⊕ B
that some convolution loop surrounds; a cell with winding <= 0 can still lie in the
sum (a hole of one operand smaller than the other: the weak spot of Sec. 6, and of
CGAL's exact sums).  So every hole ring is tested at one interior point x, as deep
inside the hole as a grid search finds (a pole of inaccessibility in the manner of
polylabel): x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅, evaluated by Clipper on A and B flattened
within a tenth of the point's depth (so the answer is the exact one for x).
"""

import numpy as np
import pyclipper

from .. import moments as mo
from .. import polyline as pl
from ..polyline import min_segment_distance, unique, winding_number


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


def _search(ring, islands, grid_n, rounds, enough=np.inf):
    """:func:`deepest_point`'s grid search on the given polygons."""
    polys = [ring] + list(islands)
    a = np.concatenate(polys)
    b = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    lo, hi = ring.min(axis=0), ring.max(axis=0)
    center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    best, depth = center, -np.inf
    for r in range(rounds):
        g = np.linspace(-1.0, 1.0, grid_n)
        cand = center + np.stack(np.meshgrid(g, g), -1).reshape(-1, 2) * half
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
    forward and back, as strokes are) count as curves: open paths in Clipper."""

    def __init__(self, region_a, region_b, depth):
        flat = depth / 10.0
        pa = pl.flatten_loops(region_a, flat)
        self.pb = pl.flatten_loops(region_b, flat)
        size = min(float(np.ptp(np.concatenate(p), axis=0).max()) for p in (pa, self.pb))
        self.grid = min(depth / 20.0, size / 1000.0)
        flat_loop = (np.abs(mo.loop_areas(region_a)) <= 1e-9 * size * size).tolist()
        self.pa = [self._int(p) for p, f in zip(pa, flat_loop) if not f]
        # a degenerate loop P, reverse(P): its first half is the path
        self.curves = [self._int(np.vstack([p, p[:1]]))[:len(p) // 2 + 1]
                       for p, f in zip(pa, flat_loop) if f]
        self.box_a = _boxes(self.pa)
        self.box_c = _boxes(self.curves)
        pts_b = np.concatenate(self.pb)
        self.box_b = np.concatenate([pts_b.min(axis=0), pts_b.max(axis=0)])

    def _int(self, pts):
        return np.rint(pts / self.grid).astype(np.int64)

    def __call__(self, x):
        # only the loops of A whose boxes meet the box of x - B can meet x - B
        lo = self._int(np.asarray(x) - self.box_b[2:]) - 1
        hi = self._int(np.asarray(x) - self.box_b[:2]) + 1
        closed = [p.tolist() for p in _meeting(self.pa, self.box_a, lo, hi) if len(p) >= 3]
        curves = [c.tolist() for c in _meeting(self.curves, self.box_c, lo, hi) if len(c) >= 2]
        if not closed and not curves:
            return False
        clip = pyclipper.Pyclipper()
        for c in closed:
            if not _add(clip, c, pyclipper.PT_SUBJECT, True):
                curves.append(c + c[:1])  # no area on the grid: its outline
        for c in curves:
            # a curve that rounds to one grid point: a segment of one unit (within
            # the flattening's depth / 10 of it)
            _add(clip, c, pyclipper.PT_SUBJECT, False) or _add(
                clip, [c[0], [c[0][0] + 1, c[0][1]]], pyclipper.PT_SUBJECT, False)
        moved = [self._int(np.asarray(x) - p) for p in self.pb]
        if not any([_add(clip, p.tolist(), pyclipper.PT_CLIP, True) for p in moved if len(p) >= 3]):
            return False  # x - B rounds to no area
        tree = clip.Execute2(pyclipper.CT_INTERSECTION, pyclipper.PFT_NONZERO,
                             pyclipper.PFT_NONZERO)
        if pyclipper.OpenPathsFromPolyTree(tree):
            return True
        return any(abs(pyclipper.Area(p)) > 0 for p in pyclipper.ClosedPathsFromPolyTree(tree))


def _add(clip, path, kind, closed):
    """Add one path to Clipper; False where Clipper refuses it (fewer than 2 distinct
    points, or a closed path with all its points on one line)."""
    try:
        return bool(clip.AddPath(path, kind, closed))
    except pyclipper.ClipperException:
        return False


def _boxes(polys):
    """(k, 4) integer boxes (xmin, ymin, xmax, ymax) of polygons."""
    if not polys:
        return np.zeros((0, 4), np.int64)
    return np.array([np.concatenate([p.min(axis=0), p.max(axis=0)]) for p in polys])


def _meeting(polys, boxes, lo, hi):
    """The polygons whose boxes meet the box [lo, hi]."""
    if not len(polys):
        return []
    hit = np.all(boxes[:, :2] <= hi, axis=1) & np.all(boxes[:, 2:] >= lo, axis=1)
    return [polys[k] for k in np.flatnonzero(hit)]

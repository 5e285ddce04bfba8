"""Calligraphic fonts from skeletons (paper Fig. 5): every skeleton glyph ⊕ a nib.

A skeleton UFO (e.g. a single-line font: every contour an open centre line) is read
with ufoLib2 (:mod:`morph.parse.ufo`); each glyph's paths are stroked with a convex
nib held at a fixed angle by :func:`morph.stroke.stroke_paths` (open path ⊕ nib: both
sides convolved with the nib plus the nib's own boundary as caps; a closed path is
stroked, not filled) and the rational pieces of the result are written as cubics with
:func:`morph.export.piece_to_cubics` (certified bound).  The output is a copy of the
source UFO with the outlines replaced (kerning, groups, features, lib kept), saved as
``.ufo`` or compiled with ufo2ft (``.otf``: CFF cubics; ``.ttf``: the UFO copy holds
TrueType quadratic splines, converted here, which ufo2ft compiles as they are).

Tolerance budget (``tol``, font units), by :func:`morph.budget.plan`:
the stroke within the geometry share (``stroke_paths``), the cubics within the export
share of the stroke's pieces (certified, Fréchet); for ``.ttf`` the export share is
split again between the cubics and their conversion to quadratic splines with cu2qu
(:func:`morph.export.loops_to_quadratics`, :data:`morph.budget.QUADRATIC_CUBIC_SHARE`;
cu2qu's check is certified up to rounding), before rounding: every point is rounded
once (ufo2ft converting rounded cubics and rounding again moved TrueType g 1.38
units).  The contours are then rounded to integers and cleaned
(:func:`morph.fonts.tables.contours_from_loops`: <= 0.71 units more), in the UFO
too, so the UFO and the compiled font hold the same outlines.  A glyph whose stroke
or conversion raises is written by the polygon fallback of
:func:`morph.fonts.jobs.polygon_sum` (lines, within ``tol`` + 1/8 unit) and named in
the returned statistics.

Metrics.  The stroke of a skeleton point p is p + nib, so a glyph grows by the nib's
extent on both sides.  Side bearings are kept: the outline is shifted right by the
nib's left extent (``-xmin``) and the advance grows by the nib's width, both rounded
to integers (outlines, anchors, component offsets and feature anchors stay on the
integer grid).  Zero-width glyphs (combining marks) keep advance 0 and are shifted by
the left extent minus the width instead, so a mark drawn after its base lands where
it did on the skeleton.  Anchors (in the glyphs and the explicit ``<anchor>`` of the
feature file, :func:`move_feature_anchors`) and vertical glyph guidelines move with
the outline; anchors also by the nib's centre (the centre of the stroke of the
anchor point).  Vertical font metrics are kept, except that
the OS/2 win ascent / descent grow to cover the new glyphs (no clipping).  PostScript
hinting values of the skeleton (blue zones, stems) are dropped: they described
hairlines.

Composites stay composites where that keeps the outline one trimmed outline: a
component is kept when the stroke commutes with its transformation M (M (g ⊕ N) =
M g ⊕ N, i.e. M N = N: a translation, or a 180-degree rotation with a centrally
symmetric nib) and its stroke stays apart from the stroke of the rest of the glyph
(:func:`separate_components`); its base glyph is stroked once, and the component
offset corrected for the two glyphs' shifts (o' = o + s_composite - M s_base).
Scaled, flipped or rotated components (fractions, superiors, mirrored punctuation)
are decomposed and stroked inside the composite, because scaling the stroked base
would scale the nib too; so is a component whose stroke may meet another part's
(e.g. a g drawn as an o component and a tail): kept, the two strokes would be
written as outlines that overlap.

Which glyphs.  ``glyphs`` (None: all) are stroked, with the base glyphs of their kept
components, and the composites not chosen that use only stroked glyphs through kept
components (e.g. eacute when e and acutecomb are) follow for free.  Every other glyph
is left empty, its advance kept, in every output: an open skeleton cannot be filled,
and a ``.ufo`` output must compile with ufo2ft as it stands (a type designer builds
the subset they asked for).  In a ``.ufo`` the skeletons of those glyphs are kept in
a layer named ``skeleton`` (:data:`SKELETON_LAYER`; not compiled), so nothing of
the source is lost.
"""

import time
import functools
from functools import partial
from pathlib import Path

import numpy as np

from .. import budget
from .. import piece as pc
from .. import polyline as pl
from ..errors import MorphError, ParseError, one_line
from ..parse.ufo import glyph_names_for
from ..nib import check_convex_nib, nib_is_symmetric, region_extent
from .fea import move_feature_anchors, moved_features
from .jobs import (CHUNK, SUM_SHARE, converting,  # noqa: F401 (CHUNK re-exported)
                   glyph_chunks, glyph_progress, run_glyph_jobs)
from .ufo_tables import grow_win_metrics, rename_ufo_family

__all__ = ["stroke_ufo", "stroke_plan", "stroke_glyph_region", "nib_is_symmetric",
           "move_feature_anchors", "DEFAULT_NIB", "SKELETON_LAYER"]

# the default broad nib: 90 x 20 units at upm 1000, long axis at 30 degrees
DEFAULT_NIB = (90.0, 20.0, 30.0)
#: the layer of a ``.ufo`` output holding the skeletons of the glyphs not stroked
SKELETON_LAYER = "skeleton"




def _default_stroker():
    from ..stroke import stroke_paths

    return stroke_paths


def stroke_glyph_region(paths, nib_region, tol, stroker=None):
    """Region of the union of ``paths`` ⊕ nib (empty list for no paths), within tol.

    Raises:
        MorphError: as the stroker (:func:`morph.stroke.stroke_paths`).
    """
    if not paths:
        return []
    stroker = stroker or _default_stroker()
    return stroker(paths, nib_region, tol)


def keep_component(component, symmetric):
    """True for a component kept as a component: a translation, or with a centrally
    symmetric nib a half turn (the stroke commutes with both)."""
    m = tuple(float(v) for v in tuple(component.transformation)[:4])
    return m == (1.0, 0.0, 0.0, 1.0) or (symmetric and m == (-1.0, 0.0, 0.0, -1.0))


#: at most how far (font units) integer rounding moves a written point (half the
#: diagonal of the unit grid cell, :func:`morph.fonts.tables.contours_from_loops`)
ROUNDING = 0.5 ** 0.5


def stroke_plan(font, glyphs, nib_region, tol=0.5):
    """``(stroked, followed)`` glyph names of a ufoLib2 font for :func:`stroke_ufo`
    at outline tolerance ``tol`` (font units).

    ``stroked``: the chosen glyphs (``glyphs``: characters or names, None: all) and
    the base glyphs of their kept components; ``followed``: composites not chosen
    that use only stroked glyphs through kept components (see the module docstring).

    Raises:
        ParseError: a character or name the font lacks.
    """
    chosen = list(font.keys()) if glyphs is None else glyph_names_for(font, glyphs)
    kept = separate_components(font, font, nib_region, tol)
    return plan_components(font, chosen, kept=kept)


def separate_components(font, source, nib_region, tol, contour_counts=None):
    """A function ``kept(name)``: for each component of glyph ``name`` whether it is
    kept as a component (True) or decomposed and stroked with the glyph (False)
    (:class:`_Separation`).  ``font``: the glyphs' components (shells will do),
    ``source``: their contours, ``contour_counts`` name -> number of contours
    (None: ``font``'s own)."""
    return _Separation(font, source, nib_region, tol, contour_counts)


class _Separation:
    """Which components of a glyph are kept (see :func:`separate_components`).

    A component is kept when the stroke commutes with its transformation
    (:func:`keep_component`) and its stroke cannot come within ``gap`` = 2 (``tol``
    + :data:`ROUNDING`) of the stroke of any other part of the glyph (its own
    contours, its other components).  Each written outline is within ``tol`` plus
    the rounding of its exact stroke, so kept parts are written as outlines that do
    not overlap, as the one trimmed outline of a static font must not; nearer parts
    are stroked together and trimmed as one.

    Two parts' strokes P ⊕ N and Q ⊕ N are that far apart when no p - q (p in P, q
    in Q) lies in (N - N) grown by ``gap``.  First the skeletons' control boxes,
    grown by the nib's extent; where those are nearer, points of the skeletons at
    most ``step`` apart, within ``step`` / 4 of the curves, against the polygon of
    (N - N)'s support in :data:`DIRECTIONS` directions (which holds N - N), grown
    by ``gap`` + 2 ``step`` (a curve point is within 3/4 step of a sample point);
    ``step`` is an eighth of the nib's larger extent.  Both tests may find parts
    near that are not (the glyph is then stroked whole, as it would be without
    components), never the other way.  The answers are kept."""

    #: the directions of the support polygon of N - N
    DIRECTIONS = 64
    #: how many of the nearest pairs of points :meth:`_points_near` tries before all
    #: of them (work only, not the answer: on Relief the first pair found inside is
    #: among the 11 nearest)
    NEAREST = 16

    def __init__(self, font, source, nib_region, tol, contour_counts=None):
        self.font, self.source, self.counts = font, source, contour_counts
        self.symmetric = nib_is_symmetric(nib_region)
        self.extent = region_extent(nib_region)
        nx0, ny0, nx1, ny1 = self.extent
        self.step = max(nx1 - nx0, ny1 - ny0) / 8.0
        self.gap = 2.0 * (tol + ROUNDING)
        ang = np.linspace(0.0, 2.0 * np.pi, self.DIRECTIONS, endpoint=False)
        self.u = np.column_stack([np.cos(ang), np.sin(ang)])
        eps = self.step / 64.0
        pts = np.concatenate([pl.flatten(p, eps)[0] for loop in nib_region for p in loop])
        d = pts @ self.u.T  # support of N - N: h(u) + h(-u), within 2 eps of the chords'
        self.reach = d.max(axis=0) - d.min(axis=0) + 2.0 * eps + self.gap + 2.0 * self.step
        self.boxes, self.answers, self.paths, self.points, self.own = {}, {}, {}, {}, {}
        self.dense = None  # glyph name -> its points (_dense_many), once read

    def __call__(self, name):
        if not self.font[name].components:  # nothing to decide: its contours are not read
            return ()
        if name not in self.answers:
            self._decide_all()
        return self.answers[name]

    def _decide_all(self):
        """The answers of every glyph with components, decided together on the first
        question: the parts' boxes (each component's its base's moved, all at once),
        the box test of every pair of parts of every glyph at once, then the point
        test (:meth:`_points_near`) of the pairs whose boxes meet, but of a pair
        whose two parts are already known near; each part's points computed once."""
        self._read_all()
        names = [g.name for g in self.font if g.components]
        comps = [list(self.font[n].components) for n in names]
        flat = [c for cs in comps for c in cs]
        moved = _moved_boxes([self._box(c.baseGlyph) for c in flat],
                             [tuple(c.transformation) for c in flat])
        boxes, at, part_of, k = [], [], [], 0
        for n, cs in zip(names, comps):
            at.append(len(boxes))
            boxes.append(self._own_box(n))
            boxes.extend(moved[k:k + len(cs)])
            part_of += [(n, None)] + [(n, c) for c in cs]
            k += len(cs)
        first, second = _glyph_pairs(np.array(at, np.int64),
                                     np.array([len(cs) + 1 for cs in comps], np.int64))
        meet = self._boxes_meet(boxes, first, second)
        parts, near = {}, np.zeros(len(boxes), bool)
        for i, j in zip(first[meet].tolist(), second[meet].tolist()):
            if near[i] and near[j]:
                continue
            for x in (i, j):   # each part's points once (a part is in several pairs)
                if x not in parts:
                    parts[x] = self._part_points(*part_of[x])
            if self._points_near(parts[i], boxes[i], parts[j], boxes[j]):
                near[i] = near[j] = True
        for n, o, cs in zip(names, at, comps):
            self.answers[n] = tuple(keep_component(c, self.symmetric) and not near[o + 1 + x]
                                    for x, c in enumerate(cs))

    def _read_all(self):
        """The skeleton paths of every glyph a separation can ask for (each glyph
        with components, each component's base), read on the first question in one
        batch (:func:`morph.parse.glif.skeleton_outlines`, all pieces built
        together; a glyph it leaves, or an open font's, by ufoLib2), and their
        points (:meth:`_dense_many`) all flattened together.  A
        :class:`morph.fonts.stream.SkeletonSource` holds the outlines for the
        strokes, which then read no file twice."""
        if self.dense is not None:
            return
        from ..parse.glif import skeleton_outlines
        from ..parse.ufo import glyph_paths

        need, bases = {}, set()
        for g in self.font:
            if g.components:
                need[g.name] = None
                for c in g.components:
                    if c.baseGlyph in self.font:
                        need[c.baseGlyph] = None
                        bases.add(c.baseGlyph)
        names = [n for n in need if self._count(n)]
        for n in need:
            self.paths[n] = []
        read = getattr(self.source, "skeleton_outlines", None)
        if read is not None:   # held for the strokes, the bases kept for decomposing
            outlines = read(names, hold=True)
            read([n for n in names if n in bases], keep=True)
        else:
            read = getattr(self.source, "glif_data", None)
            outlines = (skeleton_outlines([read(n) for n in names]) if read
                        else [None] * len(names))
        for n, outline in zip(names, outlines):
            self.paths[n] = outline[0] if outline is not None else glyph_paths(self.source[n])
        self.dense = dict(zip(names, self._dense_many([self.paths[n] for n in names])))
        self.own = dict(zip(names, _control_boxes([self.paths[n] for n in names])))

    def _count(self, name):
        return (self.counts[name] if self.counts is not None
                else len(self.font[name].contours))

    def _own_box(self, name):
        if name in self.own:   # read by :meth:`_read_all`, boxed together
            return self.own[name]
        if not self._count(name):
            return None
        xy = np.concatenate([pc.cartesian(p) for pieces, _ in self._paths(name)
                             for p in pieces] or [np.zeros((0, 2))])
        return (*xy.min(axis=0), *xy.max(axis=0)) if len(xy) else None

    def _paths(self, name):
        """The glyph's own skeleton paths, read once (:meth:`_read_all` reads them
        all)."""
        from ..parse.ufo import glyph_paths

        if name not in self.paths:
            self.paths[name] = glyph_paths(self.source[name]) if self._count(name) else []
        return self.paths[name]

    def _box(self, name):  # the control box of a glyph's skeleton, components included
        if name not in self.font:  # a missing base: the plan names it
            return None
        if name not in self.boxes:
            self.boxes[name] = None  # a cycle (refused by the plan) ends here
            parts = [self._own_box(name)] + [_moved_box(self._box(c.baseGlyph), c.transformation)
                                             for c in self.font[name].components]
            self.boxes[name] = _union_box([b for b in parts if b is not None])
        return self.boxes[name]

    def _boxes_meet(self, boxes, first, second):
        """For each pair (``first[k]``, ``second[k]``) of parts, whether their control
        boxes grown by the nib's extent and ``gap`` meet (a part without a box meets
        nothing), all tested at once."""
        live = np.array([b is not None for b in boxes])
        b = np.array([bx if bx is not None else (0.0, 0.0, 0.0, 0.0) for bx in boxes],
                     float).reshape(-1, 4)
        nx0, ny0, nx1, ny1 = self.extent
        g = self.gap
        p, q = b[first], b[second]
        apart = ((p[:, 0] + nx0 - g > q[:, 2] + nx1) | (q[:, 0] + nx0 - g > p[:, 2] + nx1)
                 | (p[:, 1] + ny0 - g > q[:, 3] + ny1) | (q[:, 1] + ny0 - g > p[:, 3] + ny1))
        return ~apart & live[first] & live[second]

    def _points_near(self, pa, a, pb, b):
        """Whether some difference of points ``pa`` (box ``a``) and ``pb`` (box
        ``b``) lies in the grown support polygon of N - N.  The polygon lies in the
        disc of radius max reach / cos(pi / DIRECTIONS) (a difference d in it has
        d . u <= reach(u) for the direction u nearest its own, within that angle), so
        only the pairs in that disc are tested against all the directions."""
        r = self.reach.max()  # a pair farther apart than this in x or y is not near
        pa = pa[np.all((pa >= np.array(b[:2]) - r) & (pa <= np.array(b[2:]) + r), axis=1)]
        pb = pb[np.all((pb >= np.array(a[:2]) - r) & (pb <= np.array(a[2:]) + r), axis=1)]
        if not len(pa) or not len(pb):
            return False
        disc = (r / np.cos(np.pi / self.DIRECTIONS)) ** 2 * (1.0 + 1e-9)
        pu, qu = _projected(pa, self.u), _projected(pb, self.u)
        rows = max(1, 2 ** 22 // len(pb))
        for k in range(0, len(pa), rows):
            d = pa[k:k + rows, None, :] - pb[None, :, :]
            d2 = d[..., 0] ** 2 + d[..., 1] ** 2
            i, j = np.nonzero(d2 <= disc)
            if len(i) == 1:   # one pair: projected by the matrix-vector product
                if np.all((pa[k + i] @ self.u.T) - (pb[j] @ self.u.T) <= self.reach):
                    return True
                continue
            # the nearest pairs first (the likeliest inside: a pair of near parts is
            # found among a few), then all; the same projections either way
            sel = np.argsort(d2[i, j], kind="stable")[:self.NEAREST]
            if np.any(np.all(pu[k + i[sel]] - qu[j[sel]] <= self.reach, axis=1)):
                return True
            # first the direction nearest each difference's own (the likeliest to
            # find it outside), then every direction of those it does not
            e = d[i, j]
            near = np.rint(np.arctan2(e[:, 1], e[:, 0]) * (self.DIRECTIONS / (2.0 * np.pi)))
            near = near.astype(np.int64) % self.DIRECTIONS
            sel = np.flatnonzero(pu[k + i, near] - qu[j, near] <= self.reach[near])
            if np.any(np.all(pu[k + i[sel]] - qu[j[sel]] <= self.reach, axis=1)):
                return True
        return False

    def _part_points(self, name, component):
        """Points of a part's skeleton (the glyph's own contours for None), at most
        ``step`` apart and within ``step`` / 4 of the curves: a component's are its
        base glyph's moved, unless its transformation stretches some direction (it
        would stretch the spacing too), then its paths' own."""
        from ..parse.ufo import component_paths

        if component is None:
            return self._own_points(name)
        m = np.array(tuple(component.transformation), float)
        if _stretches(m[:4]):
            return self._dense_many([component_paths(self.source, component)])[0]
        pts = self._glyph_points(component.baseGlyph)
        return pts @ m[:4].reshape(2, 2) + m[4:]

    def _own_points(self, name):
        if name not in self.dense:
            self.dense[name] = self._dense_many([self._paths(name)])[0]
        return self.dense[name]

    def _glyph_points(self, name):
        """:meth:`_part_points` of a whole glyph, components included, kept."""
        if name not in self.points:
            self.points[name] = np.zeros((0, 2))  # a cycle (refused by the plan) ends here
            self.points[name] = np.concatenate(
                [self._own_points(name)]
                + [self._part_points(name, c) for c in self.font[name].components])
        return self.points[name]

    def _dense_many(self, glyph_paths):
        """Points of each glyph's ``paths`` at most ``step`` apart, within ``step`` / 4
        of them, the pieces of all flattened together (:func:`morph.polyline.
        flat_starts`): each flat segment cut into equal steps, its end point once."""
        pieces = [p for paths in glyph_paths for ps, _ in paths for p in ps]
        glyph_of = np.repeat(np.arange(len(glyph_paths)),
                             [sum(len(ps) for ps, _ in paths) for paths in glyph_paths])
        if not pieces:
            return [np.zeros((0, 2)) for _ in glyph_paths]
        owner, _, starts = pl.flat_starts(pieces, self.step / 4.0)
        ends = np.array([pc.end(np.asarray(p, float)) for p in pieces])
        # each piece's polyline: its starts then its end; segments within a piece
        pts = np.concatenate([starts, ends])
        who = np.concatenate([owner, np.arange(len(pieces))])
        last = np.concatenate([np.zeros(len(owner), bool), np.ones(len(pieces), bool)])
        order = np.lexsort((last, who))
        pts, who, last = pts[order], who[order], last[order]
        seg = pts[1:] - pts[:-1]
        inner = ~last[:-1]     # a segment from a start to the next point of its piece
        seg, a = seg[inner], pts[:-1][inner]
        k = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / self.step)).astype(int)
        t = np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)
        dense = np.repeat(a, k, axis=0) + np.repeat(seg / k[:, None], k, axis=0) * t[:, None]
        dense_who = np.repeat(who[:-1][inner], k)
        out_pts = np.concatenate([dense, pts[last]])
        out_glyph = glyph_of[np.concatenate([dense_who, who[last]])]
        out_pts = out_pts[np.argsort(out_glyph, kind="stable")]
        cuts = np.searchsorted(np.sort(out_glyph), np.arange(1, len(glyph_paths)))
        return np.split(out_pts, cuts)


def _projected(pts, u):
    """``pts @ u.T`` (the points' projections on the directions ``u``), each row as
    the matrix product of two rows or more computes it: the same bits as the rows'
    product in any stack of two or more (one row alone is a matrix-vector product,
    rounded otherwise)."""
    if len(pts) == 1:
        return (np.concatenate([pts, pts]) @ u.T)[:1]
    return pts @ u.T


def _glyph_pairs(at, parts):
    """The pairs (first, second) of the parts of each glyph (its ``parts[g]`` parts
    numbered from ``at[g]``), first < second, glyphs of the same number of parts
    together."""
    first, second = [np.zeros(0, np.int64)], [np.zeros(0, np.int64)]
    for k in sorted(set(parts.tolist())):
        i, j = _pairs(k)
        o = at[parts == k][:, None]
        first.append((o + i).ravel())
        second.append((o + j).ravel())
    return np.concatenate(first), np.concatenate(second)


def _stretches(m):
    """Whether the 2 x 2 matrix ``m`` (xx, xy, yx, yy) stretches some direction
    (its largest singular value above 1 + 1e-12): sigma^2 = (F + sqrt(F^2 -
    4 det^2)) / 2, F the sum of the squares."""
    xx, xy, yx, yy = (float(v) for v in m)
    if (xx, xy, yx, yy) == (1.0, 0.0, 0.0, 1.0):
        return False
    f = xx * xx + xy * xy + yx * yx + yy * yy
    det = xx * yy - xy * yx
    s2 = 0.5 * (f + np.sqrt(max(0.0, f * f - 4.0 * det * det)))
    return bool(np.sqrt(s2) > 1.0 + 1e-12)


def _moved_box(b, transformation):
    """The box of box ``b`` under an affine ``transformation`` (xx, xy, yx, yy, dx,
    dy); None for None."""
    if b is None:
        return None
    xx, xy, yx, yy, dx, dy = (float(v) for v in tuple(transformation))
    corners = np.array([(b[0], b[1]), (b[2], b[1]), (b[0], b[3]), (b[2], b[3])])
    x = corners[:, 0] * xx + corners[:, 1] * yx + dx
    y = corners[:, 0] * xy + corners[:, 1] * yy + dy
    return (x.min(), y.min(), x.max(), y.max())


def _moved_boxes(boxes, transformations):
    """:func:`_moved_box` of many boxes (None stays None), all at once: the same
    arithmetic on the four corners."""
    live = [b is not None for b in boxes]
    b = np.array([bx if bx is not None else (0.0, 0.0, 0.0, 0.0) for bx in boxes],
                 float).reshape(-1, 4)
    t = np.array(transformations, float).reshape(-1, 6)
    cx = b[:, [0, 2, 0, 2]]
    cy = b[:, [1, 1, 3, 3]]
    x = cx * t[:, 0, None] + cy * t[:, 2, None] + t[:, 4, None]
    y = cx * t[:, 1, None] + cy * t[:, 3, None] + t[:, 5, None]
    out = np.column_stack([x.min(axis=1), y.min(axis=1), x.max(axis=1), y.max(axis=1)])
    return [tuple(row) if ok else None for row, ok in zip(out.tolist(), live)]


@functools.lru_cache(maxsize=None)
def _pairs(k):
    """The pairs (i, j), i < j < k, as two index arrays."""
    return np.triu_indices(k, 1)


def _control_boxes(glyph_paths):
    """The control box (xmin, ymin, xmax, ymax) of each glyph's skeleton ``paths``
    (None for no piece), the pieces of all glyphs boxed by degree at once and each
    glyph's boxes joined by one reduceat."""
    pieces = [p for paths in glyph_paths for ps, _ in paths for p in ps]
    count = np.array([sum(len(ps) for ps, _ in paths) for paths in glyph_paths], np.int64)
    if not pieces:
        return [None] * len(glyph_paths)
    lo, hi = np.zeros((len(pieces), 2)), np.zeros((len(pieces), 2))
    for ks, h in pc.degree_groups(pieces):
        lo[ks], hi[ks] = pc.column_extremes(pc.cartesian(h))
    has = count > 0
    at = (np.cumsum(count) - count)[has]
    box = np.concatenate([np.minimum.reduceat(lo, at), np.maximum.reduceat(hi, at)], axis=1)
    out = [None] * len(glyph_paths)
    for k, b in zip(np.flatnonzero(has).tolist(), box.tolist()):
        out[k] = tuple(b)
    return out


def _union_box(boxes):
    """The box holding all ``boxes`` (None for none)."""
    if not boxes:
        return None
    b = np.array(boxes, float)
    return (*b[:, :2].min(axis=0), *b[:, 2:].max(axis=0))


def plan_components(font, chosen, symmetric=True, contour_counts=None, kept=None):
    """:func:`stroke_plan` of the chosen glyph names.  ``kept(name)``: for each of the
    glyph's components whether it is kept (:func:`separate_components`; None: those
    :func:`keep_component` keeps, ``symmetric``: the nib is centrally symmetric).
    ``contour_counts``: glyph name -> its number of contours, for a font of shells
    (None: the glyphs' own)."""
    from ..parse.ufo import component_cycle

    if kept is None:
        def kept(name):
            return tuple(keep_component(c, symmetric) for c in font[name].components)
    cycle = component_cycle(font, chosen)
    if cycle:
        raise ParseError("glyph %r uses itself through its components: %s"
                         % (cycle[0], " => ".join(cycle)), cycle[0])
    stroked = []
    seen = set()
    todo = list(chosen)
    while todo:
        n = todo.pop(0)
        if n in seen:
            continue
        if n not in font:
            raise ParseError("component base glyph %r is missing from the UFO" % n, n)
        seen.add(n)
        stroked.append(n)
        for c, keep in zip(font[n].components, kept(n)):
            if keep and c.baseGlyph not in seen:
                todo.append(c.baseGlyph)
    followed = []
    changed = True
    while changed:
        changed = False
        for g in font:
            own = contour_counts[g.name] if contour_counts is not None else len(g.contours)
            if g.name in seen or own or not g.components:
                continue
            if all(keep and c.baseGlyph in seen for c, keep in zip(g.components, kept(g.name))):
                seen.add(g.name)
                followed.append(g.name)
                changed = True
    return stroked, followed


def _glyph_job(args):
    """Stroke one glyph and convert it to integer cubic contours (a process-pool job).

    ``args``: (name, paths, nib_region, budget, offset, stroker), the tolerances as
    :func:`morph.budget.plan` splits them.  When the exact
    stroke or its conversion raises, the glyph falls back to the polygon stroke of
    :func:`morph.fonts.jobs.polygon_sum` (within stroke_tol + cubic_tol + 1/8 unit,
    lines only) and the error is returned with it.
    """
    return _chunk_job([args])[0]


def _chunk_job(chunk):
    """:func:`_glyph_job` of several glyphs (a process-pool job): the glyphs are
    stroked together (:func:`_stroked_regions`), then the outlines of all of them
    are converted to cubics in one batch
    (:func:`morph.fonts.tables.contours_from_regions`), which costs a
    fraction of glyph-by-glyph conversion (the certified fits of all glyphs share
    each round's array calls).  If the batch raises, each glyph is converted alone,
    so that only the failing one falls back to the polygon stroke.  A glyph's
    ``seconds`` is its stroke's CPU time plus its share of the batch (by its number
    of pieces).  A glyph's ``region`` stays where it was stroked: its contours are
    moved by its placement offset, the pieces are not (the offset is horizontal,
    :func:`_stroke_work`, and only the region's y extent is used)."""
    from .tables import contours_from_loops, contours_from_regions

    out = [{"name": job[0], "contours": None, "region": r, "fallback": e, "seconds": s}
           for job, (r, e, s) in zip(chunk, _stroked_regions(chunk))]
    good = [k for k, r in enumerate(out) if r["fallback"] is None]
    t0 = time.process_time()
    tol, quadratic = _outline_tolerance(chunk[0][3])
    try:
        with converting(len(good)):
            contours = contours_from_regions([out[k]["region"] for k in good], tol, quadratic,
                                             [chunk[k][4] for k in good], reverse=False,
                                             splines=True)
    except MorphError:
        contours = None
    if contours is not None:
        sizes = np.array([sum(len(lp) for lp in out[k]["region"]) for k in good], float)
        share = (time.process_time() - t0) * sizes / max(sizes.sum(), 1.0)
        for k, c, dt in zip(good, contours, share):
            out[k]["contours"] = c
            out[k]["seconds"] += float(dt)
    else:                   # one glyph at a time: only the failing ones fall back
        for k in good:
            t0 = time.process_time()
            try:
                out[k]["contours"] = contours_from_loops(out[k]["region"], tol, quadratic,
                                                         chunk[k][4], reverse=False,
                                                         splines=True)
            except MorphError as exc:
                out[k]["fallback"] = exc
            out[k]["seconds"] += time.process_time() - t0
    for job, r in zip(chunk, out):
        if r["fallback"] is not None:
            t0 = time.process_time()
            r["contours"], r["region"], r["fallback"] = _polygon_stroke(job, r["fallback"])
            r["seconds"] += time.process_time() - t0
    return out


def _polygon_stroke(job, exc):
    """(contours, region, error text) of a glyph whose exact stroke raised ``exc``:
    the rest of the fallback ladder (:func:`morph.fonts.jobs.fallback_ladder`), the
    polygon stroke of :func:`morph.fonts.jobs.polygon_sum`; should that raise a
    MorphError too, the glyph is left empty (and named)."""
    from .jobs import error_text, fallback_ladder, polygon_sum

    name, paths, nib_region, tols, offset, _ = job

    def polygon():
        return polygon_sum([pieces for pieces, _ in paths], nib_region,
                           tols.geometry + tols.cubic, closed=False)

    kind, polys, error = fallback_ladder([("polygon", polygon)], error_text(exc))
    if kind is None:
        return [], [], error + "; left empty"
    from .jobs import polylines_to_contours

    region = [[pc.line(p[k], p[(k + 1) % len(p)]) for k in range(len(p))] for p in polys]
    return polylines_to_contours(polys, offset=offset), region, error




def _stroked_regions(chunk):
    """[(region, error, CPU seconds)] of :func:`_chunk_job`'s glyphs: with the default
    stroker all at once (:func:`morph.stroke.stroke_many`; each glyph's share of the
    time by its number of result pieces), else, or where that raises, one by one."""
    if all(job[5] is None for job in chunk):
        from ..stroke import stroke_many

        t0 = time.process_time()
        try:
            regions = stroke_many([job[1] for job in chunk], chunk[0][2], chunk[0][3].geometry)
        except MorphError:  # glyph by glyph, as they were (only a MorphError: the ladder)
            regions = None
        if regions is not None:
            glyph_progress(SUM_SHARE * len(chunk))
            sizes = np.array([sum(len(lp) for lp in r) for r in regions], float)
            share = (time.process_time() - t0) * sizes / max(sizes.sum(), 1.0)
            return [(r, None, float(s)) for r, s in zip(regions, share)]
    out = []
    for name, paths, nib_region, tols, _, stroker in chunk:
        t0 = time.process_time()
        try:
            region, error = stroke_glyph_region(paths, nib_region, tols.geometry, stroker), None
        except MorphError as exc:
            region, error = None, exc
        out.append((region, error, time.process_time() - t0))
        glyph_progress(SUM_SHARE)
    return out


def stroke_ufo(src, out_path, nib_region, glyphs=None, tol=0.5, family_name=None,
               progress=None, stroker=None, overwrite=False, jobs=1, in_flight=None,
               planned=None):
    """Write a calligraphic font: every chosen skeleton glyph of ``src`` ⊕ nib.

    ``src``: a skeleton ``.ufo`` folder, an open ``ufoLib2.Font`` (not modified) or a
    :class:`morph.fonts.stream.SkeletonSource` of either (its shell font is used).
    ``out_path``: ``.ufo`` (a copy of the source with the outlines replaced),
    ``.otf`` or ``.ttf`` (ufo2ft's tables).  ``nib_region``: a convex region in font
    units (:func:`morph.fonts.brush.ellipse_nib`), the pen point at its origin.
    ``glyphs``: characters or glyph names (None: every glyph).  ``tol``: outline
    tolerance in font units before integer rounding (the module docstring gives
    the budget).  ``family_name``: default "<family> Stroke".
    ``progress(name)`` is called after each glyph with contours to stroke (those
    without, composites of kept components, are written at no cost and not counted),
    ``in_flight(units)`` with the glyphs' worth of work reported by chunks not yet
    done (:func:`morph.fonts.jobs.run_glyph_jobs`).  ``stroker``: a function
    ``(paths, nib_region, tol) -> region`` (default :func:`morph.stroke.stroke_paths`).
    ``overwrite``: replace an existing output.  ``jobs``: worker processes for the
    strokes (1: in this process).  ``planned(n)`` is called with the number of
    glyphs with contours to stroke once they are known (before any is stroked).

    The font is streamed (:mod:`morph.fonts.stream`): the skeletons are read chunk
    by chunk as the workers need them, each stroked glyph comes back compiled (CFF
    charstring or glyf bytes; for a UFO its .glif is written at once), so memory
    does not grow with the glyphs' outlines.

    Returns a dict: ``glyphs`` (stroked: chosen and their bases), ``followed``
    (composites kept without being chosen), ``composites`` (written glyphs that keep
    components), ``decomposed`` (components decomposed because of a transformation),
    ``emptied`` (glyphs not chosen, left empty), ``contours``, ``points`` (on-
    and off-curve points written), ``stroke_seconds`` (CPU time of the strokes and
    their conversion, summed over the glyphs), ``seconds`` (wall, whole call),
    ``fallback`` (glyph -> the MorphError that sent it to the polygon stroke: such a
    glyph does not stop the font), ``inked`` (the glyphs that draw something), ``cmap``
    (the written font's code point -> glyph name where morph compiled it, else None),
    ``font`` (the written data and shells: ``ufoLib2.Font`` or light ``LightFont``).

    Raises:
        ParseError: unreadable UFO, a glyph or component base the UFO lacks, a bad
            contour, features that do not parse.
        NibError: a nib that is not one convex loop.
        MorphError: an output that exists without ``overwrite``; ufo2ft failing;
            feature anchors whose glyphs moved by different offsets.
        ValueError: tol <= 0 or an output suffix other than .ufo/.otf/.ttf.
    """
    from .tables import save_atomically

    t_start = time.perf_counter()
    out_path, kind = _checked_output(out_path, tol, overwrite)
    check_convex_nib(nib_region)
    plan = _uncollected(_font_plan, src, nib_region, glyphs, family_name, kind, tol)
    if planned is not None:
        planned(sum(1 for n in plan.stroked if plan.weights[n] > 0))
    save_atomically(out_path, lambda tmp: _write_streamed(
        plan, tmp, out_path, kind, nib_region, tol, progress, stroker, jobs, in_flight),
        overwrite)
    plan.stats.update(glyphs=len(plan.stroked), followed=len(plan.followed), font=plan.font,
                      seconds=time.perf_counter() - t_start)
    return plan.stats


def _uncollected(call, *args):
    """``call(*args)`` with Python's cyclic garbage collector off (on again after,
    where it was on).  The font's plan (the glyphs' shells, feaLib's syntax tree of
    the feature file) and its compilation (fontTools' tables) make some hundred
    thousand objects that live until the font is written: every 700 allocations
    would start a pass over the young objects, which live on (about 45 M
    instructions of Relief's plan and layout tables)."""
    import gc

    if not gc.isenabled():
        return call(*args)
    gc.disable()
    try:
        return call(*args)
    finally:
        gc.enable()


class _FontPlan:
    """What :func:`stroke_ufo` writes (:func:`_font_plan`): ``source`` the
    :class:`morph.fonts.stream.SkeletonSource`, ``font`` the shells (ufoLib2.Font),
    final furniture, ``stroked`` and ``followed`` glyph names, ``place`` the
    :class:`_Placement`, ``kept`` glyph name -> for each component, whether it is
    kept, ``stats``, ``features`` feaLib's tree of the moved feature file
    (:func:`_move_feature_file`), ``weights`` glyph name -> its weight for the chunks
    (:func:`_stroke_weights`).  Plain classes (this one and :class:`_Placement`):
    processing a dataclass costs every process about half a ms."""

    def __init__(self, source, font, stroked, followed, place, kept, stats, features=None,
                 weights=None):
        self.source, self.font, self.stroked, self.followed = source, font, stroked, followed
        self.place, self.kept, self.stats = place, kept, stats
        self.features, self.weights = features, weights


def _font_plan(src, nib_region, glyphs, family_name, kind, tol):
    """The source, the font of shells with its final furniture and names, the glyphs
    to stroke and those that follow, where they go; the first statistics
    (:func:`_finish_shells`)."""
    from .stream import SkeletonSource

    source = src if isinstance(src, SkeletonSource) else SkeletonSource(src)
    font = source.shell_font()
    chosen = list(font.keys()) if glyphs is None else glyph_names_for(font, glyphs)
    keep = separate_components(font, source, nib_region, tol, source.contour_counts)
    stroked, followed = plan_components(font, chosen, contour_counts=source.contour_counts,
                                        kept=keep)
    kept = {n: keep(n) for n in stroked + followed if font[n].components}
    weights = _stroke_weights(font, stroked, kept, source.contour_counts)
    place = _placement(font, stroked + followed, nib_region)
    stats, features = _finish_shells(font, source, stroked, followed, place, kept, kind)
    rename_ufo_family(font.info, family_name or "%s Stroke" % (font.info.familyName or "Morph"))
    return _FontPlan(source, font, stroked, followed, place, kept, stats, features, weights)


#: A stroked glyph of average work, for the chunks' bound (:data:`morph.fonts.jobs.
#: CHUNK` of them): this many skeleton contours (the hanzi of Make Me a Hanzi have
#: 11.8 strokes a glyph, Relief's stroked glyphs 1.7): a chunk's memory and work go
#: with its contours, not its glyphs.
CONTOURS_PER_GLYPH = 12


def _stroke_weights(font, stroked, kept, counts):
    """Glyph name -> its weight for :func:`morph.fonts.jobs.glyph_chunks`: the
    skeleton contours it strokes (its own, ``counts``, and those of the components
    it does not keep, ``kept``, through nested components) in glyphs of
    :data:`CONTOURS_PER_GLYPH`; 0 for a glyph with nothing to stroke (no contour,
    every component kept).  ``font``: the shells with the source's components."""
    whole = {}

    def decomposed(name):   # every contour of a glyph, its components' included
        if name not in whole:
            whole[name] = 0  # a component cycle is refused upstream; this ends one anyway
            whole[name] = counts.get(name, 0) + sum(
                decomposed(c.baseGlyph) for c in font[name].components if c.baseGlyph in font)
        return whole[name]

    return {n: (counts.get(n, 0) + sum(decomposed(c.baseGlyph) for c, keep in
                                       zip(font[n].components, kept.get(n, ()))
                                       if not keep and c.baseGlyph in font))
            / CONTOURS_PER_GLYPH for n in stroked}


def _write_streamed(plan, tmp, out_path, kind, nib_region, tol, progress, stroker, jobs,
                    in_flight=None):
    """Stroke the plan's glyphs chunk by chunk (each chunk's jobs read from the source
    when a process needs them) and write the font at ``tmp`` as they come
    (:class:`_StreamedGlyphs`); the statistics go to ``plan.stats``.  Only the glyphs
    with something to stroke (weight > 0, :func:`_stroke_weights`) go to the chunks,
    chunked by their weights (skeleton contours), so that as many glyphs as memory
    allows share an export batch, whose rounds cost about the same however many
    glyphs share them (Relief's 321 glyphs with contours weigh 45 glyphs' worth and
    are one batch: fit and certificate cost 1.9 ms of CPU a glyph, against 3.7 when
    counted by glyphs in 7 batches, bench/stroke_profile.py).  The others, composites
    of kept components, are written empty here (their components are in the shells)
    and not counted by ``progress``.
    """
    tols = budget.plan(tol, kind == ".ttf")

    sink = _StreamedGlyphs(plan.font, kind, tmp, progress,
                           [n for n in plan.stroked + plan.followed if plan.font[n].components],
                           plan.features)
    inked = [n for n in plan.stroked if plan.weights[n] > 0]
    for names in glyph_chunks([n for n in plan.stroked if not plan.weights[n] > 0]):
        for r in _blank_results(_FLAVORS[kind], names):
            sink.add(r, counted=False)
    if jobs > 1 and plan.source.path is not None:  # the workers read the skeletons
        import uuid

        plan.source.drop_outlines()   # those the plan held for this process's strokes

        func = partial(_read_and_stroke, _FLAVORS[kind], (plan.source.path, uuid.uuid4().hex),
                       plan.kept, nib_region, tols, stroker)
        work, prepare = [(n, plan.place.shifts[n]) for n in inked], None
    else:  # this process reads each chunk's skeletons as the chunk is due
        func, work = partial(_streamed_chunk, _FLAVORS[kind]), inked
        prepare = partial(_stroke_work, plan.source, kept=plan.kept,
                          nib_region=nib_region, tols=tols, shifts=plan.place.shifts,
                          stroker=stroker)
    run_glyph_jobs(func, work, jobs=jobs, keep=False, each=sink.add, prepare=prepare,
                   in_flight=in_flight, preload=_WORKER_MODULES + _COMPILERS.get(kind, ()),
                   weights=[plan.weights[n] for n in inked])
    grow_win_metrics(plan.font, *sink.written_extent())
    _uncollected(sink.finish, out_path, tol, jobs)
    plan.stats.update(sink.stats)
    # which glyphs draw something, for the sample's choice without reading the font
    plan.stats["inked"] = sink.inked_glyphs()


def _blank_results(flavor, names):
    """:func:`_streamed_chunk`'s results for glyphs with nothing to stroke: an empty
    outline each, made in this process (no job)."""
    return _compiled_results(flavor, [{"name": n, "contours": [], "fallback": None,
                                       "seconds": 0.0} for n in names])


def _read_and_stroke(flavor, source, kept, nib_region, tols, stroker, chunk):
    """:func:`_streamed_chunk` of ``chunk`` ((glyph name, shift) pairs), its jobs read
    in this process (a worker) from ``source`` (the UFO's path and the run's token,
    :func:`morph.fonts.stream.worker_source`): the calling process neither reads
    the skeletons nor sends them (it did 3.5 ms a hanzi glyph of a run's serial
    work, reading and pickling)."""
    from .stream import worker_source

    return _streamed_chunk(flavor, _stroke_work(worker_source(*source), [n for n, _ in chunk],
                                                kept, nib_region, tols, dict(chunk),
                                                stroker))


#: what a worker compiles a stroked glyph to, by output (None: the UFO's contours)
_FLAVORS = {".otf": "cff", ".ttf": "glyf", ".ufo": None}

#: what a chunk job imports as it runs (reading the skeletons, the strokes, the
#: curve fitting and its quadrature nodes), and by output what the quadratic
#: conversion imports: imported before worker
#: processes are forked so that they share them
#: (:func:`morph.fonts.jobs.preload_modules`)
_WORKER_MODULES = ("morph.parse.glif", "morph.stroke", "morph.fonts.tables", "morph.export",
                   "morph.fonts.stream", "morph.quadrature", "morph.parse.light_ufo")
_COMPILERS = {".ttf": ("fontTools.cu2qu",)}


def _streamed_chunk(flavor, chunk):
    """:func:`_chunk_job` of a chunk, then what the main process keeps of each glyph:
    ``outline`` (:func:`morph.fonts.stream.compile_outline` of its contours in
    ``flavor``; for None the contours themselves), ``contours`` and ``points``
    (counts) and ``box`` (xMin, yMin, xMax, yMax of the written outline, None for
    none, from the boxes the compilation computes: CFF and UFO cubics their tight
    boxes, glyf its points' boxes); the regions are not sent back."""
    return _compiled_results(flavor, _chunk_job(chunk))


def _compiled_results(flavor, out):
    """The glyph results ``out`` of :func:`_chunk_job` (or of :func:`_blank_results`)
    as :func:`_streamed_chunk` sends them: compiled, counted, boxed."""
    from .stream import compile_outlines, outline_bounds
    from ..outline import Outline

    outlines = [Outline.from_contours(r["contours"]) for r in out]
    if flavor is None:
        compiled, boxes = outlines, outline_bounds(outlines)
    else:
        compiled = compile_outlines(outlines, flavor)
        boxes = [box for _, box in compiled]
    for r, outline, done, box in zip(out, outlines, compiled, boxes):
        r.pop("region", None)
        r.update(box=box, contours=len(outline), points=outline.point_count(), outline=done)
    return out


class _StreamedGlyphs:
    """The main process's end of the stream: each stroked glyph's result
    (:func:`_streamed_chunk`) counted in ``stats``, its y range in ``extent``, its
    outline kept as bytes (``.otf``, ``.ttf``) or written to the UFO at ``tmp`` at
    once (:class:`morph.fonts.stream.UfoGlyphWriter`); ``progress(name)`` after
    each.  The boxes of the glyphs that ``composites`` (the written glyphs with
    components) place are kept for :meth:`written_extent`.  :meth:`finish` writes
    the font."""

    def __init__(self, font, kind, tmp, progress, composites=(), features=None):
        from .stream import OutlineStore, UfoGlyphWriter

        self.font, self.kind, self.tmp, self.progress = font, kind, tmp, progress
        self.features = features   # the font's feature file parsed (None: ufo2ft parses it)
        self.ufo = UfoGlyphWriter(font, tmp) if kind == ".ufo" else None
        self.store = OutlineStore() if self.ufo is None else {}   # compact, on disk
        self.extent = [None, None]
        self.composites = list(composites)
        self.boxes = dict.fromkeys(_placed_bases(font, self.composites))
        self.stats = {"contours": 0, "points": 0, "fallback": {}, "stroke_seconds": 0.0,
                      "cmap": None}
        self.inked = set()   # the stroked glyphs with an outline

    def add(self, r, counted=True):
        """Take glyph result ``r``; ``counted``: call ``progress`` for it."""
        st = self.stats
        st["stroke_seconds"] += r["seconds"]
        st["contours"] += r["contours"]
        st["points"] += r["points"]
        if r["fallback"]:
            st["fallback"][r["name"]] = r["fallback"]
        self._grow(r["box"])
        if r["box"] is not None:
            self.inked.add(r["name"])
        if r["name"] in self.boxes:
            self.boxes[r["name"]] = r["box"]
        if self.ufo is not None:
            self.ufo.write(r["name"], r["outline"])
        else:
            self.store[r["name"]] = r["outline"]
        if counted and self.progress is not None:
            self.progress(r["name"])

    def _grow(self, box):
        if box is not None:
            bottom, top = box[1], box[3]
            self.extent = [bottom if self.extent[0] is None else min(self.extent[0], bottom),
                           top if self.extent[1] is None else max(self.extent[1], top)]

    def written_extent(self):
        """[bottom, top] of every written glyph: the stroked outlines and the
        composites, whose components may move their bases above or below them."""
        memo = {}
        for name in self.composites:
            self._grow(_composite_box(self.font, name, self.boxes, memo))
        return self.extent

    def inked_glyphs(self):
        """The written glyphs that draw something: the stroked glyphs with an outline
        and the composites whose components place one (:func:`_composite_box`), as
        the font's outlines tell (a CFF font's decomposed composites, a TrueType
        font's components)."""
        memo = {}
        return frozenset(self.inked).union(
            n for n in self.composites
            if _composite_box(self.font, n, self.boxes, memo) is not None)

    def finish(self, out_path, tol, jobs=1):
        """The UFO's font info rewritten, or the font compiled by ufo2ft from the
        shells and the stored outlines and saved (a large CFF font's subroutine
        groups ``jobs`` at a time, :func:`morph.fonts.subrs.font_subroutines`)."""
        if self.ufo is not None:
            self.ufo.finish()
            return
        from .stream import compile_stored, save_font

        options = {}
        if self.kind == ".ttf":
            upm = self.font.info.unitsPerEm or 1000
            options["cubicConversionError"] = budget.plan(tol, True).cu2qu / upm
        light = getattr(self.font, "light", False)  # tables without ufo2ft
        try:
            if light:
                from .tables_static import compile_static

                otf = compile_static(self.font, self.store, self.kind,
                                     features=self.features, jobs=jobs, **options)
            else:
                otf = compile_stored(self.font, self.store, self.kind,
                                     features=self.features, **options)
        except Exception as exc:  # ufo2ft and feaLib raise many types for a source they refuse
            raise MorphError("%s could not compile %s: %s"
                             % ("morph" if light else "ufo2ft", Path(out_path).name,
                                one_line(exc))) from exc
        finally:
            self.store.close()
        # the boxes (head, hhea, maxp) are set (ufo2ft's subroutinizing save for CFF,
        # the stored glyphs' headers for glyf): not again from every glyph decoded
        otf.recalcBBoxes = False
        self.stats["cmap"] = getattr(otf, "written_cmap", None)
        save_font(otf, self.tmp)


def _placed_bases(font, composites):
    """The glyphs the components of ``composites`` place, through nested
    composites."""
    seen, todo = set(), [c.baseGlyph for n in composites for c in font[n].components]
    while todo:
        name = todo.pop()
        if name not in seen and name in font:
            seen.add(name)
            todo.extend(c.baseGlyph for c in font[name].components)
    return seen


def _composite_box(font, name, own, memo):
    """The box of glyph ``name`` as written: its own outline's (``own``, None or
    absent for none) and those of its components' bases, each through its
    transformation (the transformed corners bound the transformed outline).
    ``memo`` holds the boxes found so far."""
    if name not in memo:
        memo[name] = None  # a component cycle is refused upstream; this ends one anyway
        boxes = [own.get(name)]
        for comp in font[name].components:
            base = _composite_box(font, comp.baseGlyph, own, memo) \
                if comp.baseGlyph in font else None
            if base is not None:   # a few numbers: Python's arithmetic, not numpy's calls
                xx, xy, yx, yy, dx, dy = (float(v) for v in comp.transformation)
                corners = [(x, y) for x in (base[0], base[2]) for y in (base[1], base[3])]
                tx = [xx * x + yx * y + dx for x, y in corners]
                ty = [xy * x + yy * y + dy for x, y in corners]
                boxes.append((min(tx), min(ty), max(tx), max(ty)))
        boxes = [b for b in boxes if b is not None]
        memo[name] = None if not boxes else (min(b[0] for b in boxes), min(b[1] for b in boxes),
                                             max(b[2] for b in boxes), max(b[3] for b in boxes))
    return memo[name]


def _finish_shells(font, source, stroked, followed, place, kept, kind):
    """The shells' final furniture before any glyph is stroked (a UFO output writes
    them first): components, anchors, guidelines and advances moved, the glyphs not
    chosen emptied, the feature file's anchors moved.  Returns the first statistics
    (``decomposed``, ``composites``, ``emptied``) and the moved feature file's feaLib
    tree (:func:`_move_feature_file`)."""
    written = stroked + followed
    decomposed = sum(1 for n in stroked for keep in kept.get(n, ()) if not keep)
    _move_furniture(font, written, place, kept)
    emptied = _empty_unstroked(font, source, set(written), kind)
    features = _move_feature_file(font, place)
    return {"decomposed": decomposed, "emptied": emptied,
            "composites": sum(1 for n in written if font[n].components)}, features


def _checked_output(out_path, tol, overwrite):
    """(path, suffix) of the output.

    Raises:
        ValueError: tol <= 0; a suffix other than .ufo/.otf/.ttf.
        MorphError: the output exists and ``overwrite`` is false.
    """
    if not tol > 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    out_path = Path(out_path)
    kind = out_path.suffix.lower()
    if kind not in (".ufo", ".otf", ".ttf"):
        raise ValueError("output must end in .ufo, .otf or .ttf, got %s" % out_path)
    if out_path.exists() and not overwrite:
        raise MorphError("%s exists (pass overwrite=True to replace it)" % out_path)
    return out_path, kind


class _Placement:
    """Where the stroked glyphs go, on the integer grid (see the module docstring):
    ``shifts`` glyph name -> x shift of the outline; ``grow`` the advance growth (nib
    width); ``centre`` the nib's centre (anchors move by shift + centre)."""

    def __init__(self, shifts, grow, centre):
        self.shifts, self.grow, self.centre = shifts, grow, centre

    def anchor_offset(self, name):
        """(dx, dy) of a glyph's anchors; None for a glyph that is not written anew."""
        if name not in self.shifts:
            return None
        return self.shifts[name] + self.centre[0], self.centre[1]


def _placement(font, names, nib_region):
    """The :class:`_Placement` of the glyphs ``names`` for this nib: outlines shifted
    right by the nib's left extent, zero-width glyphs left by its width on top."""
    nx0, ny0, nx1, ny1 = region_extent(nib_region)
    grow = int(round(nx1 - nx0))
    centre = (int(round((nx0 + nx1) / 2.0)), int(round((ny0 + ny1) / 2.0)))
    shifts = {n: int(round(-nx0)) - (grow if font[n].width == 0 else 0) for n in names}
    return _Placement(shifts, grow, centre)


def _stroke_work(source, names, kept, nib_region, tols, shifts, stroker):
    """The jobs of :func:`_glyph_job` for the stroked glyphs ``names``: the paths of
    each, its own contours and the components that cannot be kept, read from the
    source now (:class:`morph.fonts.stream.SkeletonSource`): the chunk's ``.glif``
    files in one batch (:meth:`~morph.fonts.stream.SkeletonSource.skeleton_outlines`:
    the same paths, all pieces built together; those the plan read are not read
    again), then the bases of the decomposed components a nesting level at a time
    (:func:`_read_bases`), a glyph the array reader leaves (or an open font's) by
    ufoLib2."""
    from ..parse.ufo import component_paths, glyph_paths

    outlines = source.skeleton_outlines(names)
    _read_bases(source, [c for n, o in zip(names, outlines) if o is not None and o[1]
                         for c, keep in zip(o[1], kept[n]) if not keep])
    work = []
    for n, outline in zip(names, outlines):
        if outline is None:  # an open font, or a glyph the array reader leaves to ufoLib2
            g = source[n]
            outline = glyph_paths(g), g.components
        paths, components = outline
        for c, keep in zip(components, kept[n] if components else ()):
            if not keep:
                paths.extend(component_paths(source, c))
        # horizontal: a stroked region's y extent holds for the moved glyph (_chunk_job)
        work.append((n, paths, nib_region, tols, (float(shifts[n]), 0.0), stroker))
    return work


def _read_bases(source, components):
    """The base glyphs of ``components`` read into ``source`` for the run, through
    their nested components, each nesting level's in one batch
    (:meth:`morph.fonts.stream.SkeletonSource.skeleton_outlines`), for
    :func:`morph.parse.ufo.component_paths` to decompose; nothing is raised here
    (a missing or unreadable base is named where it is decomposed)."""
    names, seen = [c.baseGlyph for c in components], set()
    for _ in range(33):  # component_paths refuses deeper nesting
        names = [n for n in dict.fromkeys(names) if n not in seen and n in source]
        if not names:
            return
        seen.update(names)
        names = [c.baseGlyph for o in source.skeleton_outlines(names, keep=True)
                 if o is not None for c in o[1]]


def _move_furniture(font, names, place, kept):
    """Kept components re-placed (o' = o + s_composite - M s_base), anchors and
    vertical guidelines moved, advances grown, for the written glyphs ``names``."""
    for n in names:
        g = font[n]
        s = place.shifts[n]
        placed = []
        for c, keep in zip(g.components, kept.get(n, ())):
            if keep:  # the others are in the stroke
                xx, xy, yx, yy, dx, dy = tuple(c.transformation)
                sb = place.shifts[c.baseGlyph]
                c.transformation = (xx, xy, yx, yy, dx + s - xx * sb, dy - xy * sb)
                placed.append(c)
        g.components[:] = placed
        dx, dy = place.anchor_offset(n)
        for a in g.anchors:
            a.x += dx
            a.y += dy
        for gl in g.guidelines:
            if gl.x is not None and gl.y is None:
                gl.x += s
        if g.width:
            g.width = g.width + place.grow


def _empty_unstroked(font, source, done, kind):
    """Clear the skeletons of the glyphs not written anew (an open skeleton cannot be
    filled; a written UFO must compile), keeping their advances; in a ``.ufo`` output
    their skeletons go to the :data:`SKELETON_LAYER` layer.  ``font``: the shells
    (no contours: ``source.contour_counts`` tells which had some).  How many were
    cleared."""
    emptied = [g for g in font if g.name not in done
               and (source.contour_counts.get(g.name) or g.components)]
    if emptied and kind == ".ufo":
        layer = font.layers.get(SKELETON_LAYER) or font.layers.newLayer(SKELETON_LAYER)
        for g in emptied:
            layer.insertGlyph(source[g.name], overwrite=True, copy=True)
    for g in emptied:
        g.clearContours()
        g.clearComponents()
    return len(emptied)


def _move_feature_file(font, place):
    """The feature file's explicit anchors moved like their glyphs' anchors; returns
    feaLib's tree of the moved file, parsed here once for the compiler too (None:
    nothing moved, or a file with includes: :func:`morph.fonts.fea.moved_features`)."""
    if "anchor" in (font.features.text or ""):
        font.features.text, tree = moved_features(font.features.text, font.keys(),
                                                  place.anchor_offset)
        return tree
    return None


def _outline_tolerance(budget):
    """(tolerance, quadratic) of the outlines written into the UFO for a
    :class:`morph.budget.Budget`: cubics within the cubic share, or for TrueType
    quadratic splines within cubic + cu2qu (:func:`morph.export.loops_to_quadratics`
    splits it the same way), so that ufo2ft has nothing to convert and every point is
    rounded to an integer once."""
    return budget.export, budget.cu2qu > 0

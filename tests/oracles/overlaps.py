"""Overlaps inside the glyphs of a written font: the check that a static output is
"trimmed and free of overlaps".

A measure against the union (the boundary Hausdorff distance to a Clipper reference,
the exact membership predicate) cannot see two outer contours of one glyph that
overlap: the nonzero fill of the two is the union, and the union can be right.  This
oracle looks at the contours themselves.  For one glyph:

- every contour is flattened within ``flat`` font units (quadratic and cubic segments
  sampled uniformly, the number of chords from Wang's bound on the second
  differences of the control points: no project code is used);
- the polylines are noded and cut into the faces of their arrangement
  (``shapely.polygonize``); each face gets the winding number of all contours at an
  interior point (:func:`tests.oracles.reference.winding_number`);
- with ``s`` the sign of the glyph's total signed area (outer contours are
  counter-clockwise in CFF and clockwise in TrueType; the sign says which), a face
  where ``w s >= 2`` (covered by two same-orientation contours: two outer loops
  crossing, a hole inside two outers) or ``w s < 0`` (a hole contour poking out of its
  outer, a twist in one contour) is an overlap: a point-set fill is one layer deep
  everywhere only when every face has ``w s`` 0 or 1.  Faces of one overlap are
  merged; each overlap is reported with its area, its width (twice the radius of its
  largest inscribed circle, ``shapely.maximum_inscribed_circle``), the winding
  number and the inscribed circle's centre.
- Independently of the flattening, skia-pathops computes the glyph's *excess* on
  the exact curves: ``s`` x the sum of the contours' signed areas minus the area of
  their nonzero union (``pathops.simplify``).  It is the integral of ``w s - [w != 0]``:
  0 without overlaps, the lens area for two outer contours crossing once (negative
  for a poking hole).  It cross-checks the faces: a glyph whose excess is not 0 has an
  overlap.

Nested contours are no overlap: an outer contour in the hole of another (回) gives
``w s`` 1 there, as the fill should be.

The bound (:func:`overlap_bound`): the exact sum is a set, so its boundary loops never
cross.  A written contour lies within ``e = tol + ROUNDING`` of the exact boundary
(``tol`` the font's tolerance in font units: sum and curve fit together; ``ROUNDING``
the integer coordinates' half-diagonal), so where the exact sum has a gap narrower than
``2 e`` between two of its loops (the engine's documented narrow-feature limit is about
that wide: such a gap may close), the written contours on its two sides may cross it,
each by at most ``e``.  The region they then cover twice is a lens at most ``2 e``
wide (measured across the gap, where the boundaries are straight on the scale of e).
The bound bounds that width, the overlap's thickness; an overlap's area is not bounded
(a lens can be long) and is reported only.  A wider overlap is a defect (a loop kept
that the trimming should have merged, or a contour crossing its neighbour by more than
the error the outline is allowed).
"""

import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from tests.oracles import need

shapely = need("shapely", "the overlap check's faces")
pathops = need("pathops", "the overlap check's exact areas")

from fontTools.pens.basePen import BasePen  # noqa: E402 - after the optional imports
from fontTools.pens.recordingPen import DecomposingRecordingPen  # noqa: E402 - as above

from tests.oracles.reference import winding_number  # noqa: E402 - as above

#: Integer coordinates move a point by at most sqrt(2)/2 font units.
ROUNDING = 0.71
#: Faces smaller than this (font units²) are the noding's floating-point noise where two
#: contours touch (1e-27 seen), not overlaps: a lens this small is under 1e-4 units wide.
NOISE_AREA = 1e-9
#: Flattening of the written curves (font units): an overlap's width is measured within
#: about twice this.
FLAT = 0.01


def overlap_bound(tol):
    """The widest overlap a glyph written within ``tol`` font units (then rounded to
    integers) may have: ``2 (tol + ROUNDING)`` (see the module doc)."""
    return 2.0 * (tol + ROUNDING)


class Overlap(NamedTuple):
    area: float      # font units²
    width: float     # twice the largest inscribed circle's radius, font units
    winding: int     # w s of the face with the largest |w s - 1| in it
    x: float         # the inscribed circle's centre
    y: float
    excess: float    # its faces' share of the glyph's excess: (w s - 1) area for
    #                  w s >= 2, -(|w s| + 1) area for w s < 0


class GlyphOverlaps(NamedTuple):
    name: str
    contours: int
    overlaps: list   # [Overlap], widest first
    excess: float    # s * sum of signed areas - area of the nonzero union (pathops)

    @property
    def width(self):
        return max((o.width for o in self.overlaps), default=0.0)

    @property
    def area(self):
        return sum(o.area for o in self.overlaps)

    @property
    def disagreement(self):
        """|pathops' excess on the curves - the faces' excess on the flattened
        contours|: about the flattening's error (FLAT x the overlaps' perimeter), a
        larger one says one of the two computations is wrong."""
        return abs(self.excess - sum(o.excess for o in self.overlaps))


# ------------------------------------------------------------------ reading glyphs

class _FlatteningPen(BasePen):
    """Closed polylines ((n, 2) arrays, last point not repeated) of what is drawn, each
    segment within ``flat`` of its curve."""

    def __init__(self, flat=FLAT, glyphSet=None):
        super().__init__(glyphSet)
        self.flat, self.contours, self._cur = flat, [], None

    def _moveTo(self, pt):
        self._end()
        self._cur = [tuple(map(float, pt))]

    def _lineTo(self, pt):
        self._cur.append(tuple(map(float, pt)))

    def _sample(self, ctrl):
        ctrl = np.asarray([self._cur[-1]] + [tuple(map(float, p)) for p in ctrl])
        d = len(ctrl) - 1
        m = np.abs(np.diff(ctrl, 2, axis=0)).max() * math.sqrt(2) if d > 1 else 0.0
        n = max(1, math.ceil(math.sqrt(d * (d - 1) * m / (8.0 * self.flat)))) if m else 1
        t = np.arange(1, n + 1)[:, None] / n
        pts = sum(math.comb(d, k) * t ** k * (1 - t) ** (d - k) * ctrl[k]
                  for k in range(d + 1))
        self._cur += [tuple(p) for p in pts]

    def _curveToOne(self, p1, p2, p3):
        self._sample((p1, p2, p3))

    def _qCurveToOne(self, p1, p2):
        self._sample((p1, p2))

    def _closePath(self):
        self._end()

    def _endPath(self):  # a filled font closes every contour
        self._end()

    def _end(self):
        if self._cur:
            pts = np.asarray(self._cur)
            if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
                pts = pts[:-1]
            if len(pts) >= 3:
                self.contours.append(pts)
        self._cur = None


def font_glyphs(path, names=None):
    """[(glyph name, drawing)] of a written .otf/.ttf/.woff(2) or UFO, components
    decomposed: ``drawing`` is a :class:`DecomposingRecordingPen` to replay."""
    path = Path(path)
    if path.suffix.lower() == ".ufo" or path.is_dir():
        import ufoLib2

        font = ufoLib2.Font.open(str(path))
        gs, order = font, list(font.glyphOrder) or sorted(font.keys())
    else:
        from fontTools.ttLib import TTFont

        font = TTFont(str(path))
        gs, order = font.getGlyphSet(), font.getGlyphOrder()
    out = []
    for name in (order if names is None else names):
        pen = DecomposingRecordingPen(gs)
        gs[name].draw(pen)
        out.append((name, pen))
    return out


# ------------------------------------------------------------------ the check

def _signed_area(pts):
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def faces(contours, sign=None):
    """(faces, w s) of closed polylines ``contours``: the faces of their arrangement
    (shapely polygons, those over NOISE_AREA) and each face's winding number times
    the outer contours' orientation ``sign`` (+1 counter-clockwise; by default the
    sign of the total signed area)."""
    contours = [np.asarray(c, float) for c in contours if len(c) >= 3]
    if not contours:
        return np.array([], dtype=object), np.array([], dtype=np.int64)
    if sign is None:
        sign = 1 if sum(_signed_area(c) for c in contours) >= 0 else -1
    rings = [shapely.LineString(np.vstack([c, c[:1]])) for c in contours]
    noded = shapely.union_all(rings)
    found = shapely.get_parts(shapely.polygonize(shapely.get_parts(noded)))
    found = found[shapely.area(found) > NOISE_AREA]
    if not len(found):
        return found, np.array([], dtype=np.int64)
    pts = shapely.get_coordinates(shapely.point_on_surface(found))
    return found, sign * winding_number(pts, contours)


def polygon_overlaps(contours, sign=None, flat=FLAT):
    """[:class:`Overlap`] of closed polylines ``contours`` filled by the nonzero rule
    (see the module doc); ``sign``: the outer contours' orientation (+1
    counter-clockwise), by default the sign of the total signed area."""
    found, ws = faces(contours, sign)
    bad = (ws >= 2) | (ws < 0)
    if not bad.any():
        return []
    pts = shapely.get_coordinates(shapely.point_on_surface(found))
    weight = np.where(ws >= 2, ws - 1, -(np.abs(ws) + 1)) * shapely.area(found)
    merged = shapely.get_parts(shapely.union_all(found[bad]))
    out = []
    for part in merged:
        inside = shapely.contains_xy(part, pts[:, 0], pts[:, 1]) & bad
        w = ws[inside]
        worst = int(w[np.argmax(np.abs(w - 1))]) if len(w) else 2
        mic = shapely.maximum_inscribed_circle(part, flat / 4)
        (cx, cy), _ = shapely.get_coordinates(mic)
        out.append(Overlap(float(part.area), 2.0 * float(mic.length), worst,
                           float(cx), float(cy), float(weight[inside].sum())))
    return sorted(out, key=lambda o: -o.width)


def pathops_excess(drawing, sign):
    """``sign`` x the sum of the contours' signed areas minus the area of their nonzero
    union, on the exact curves (skia-pathops)."""
    path = pathops.Path()
    drawing.replay(path.getPen())
    total = 0.0
    for c in path.contours:
        # pathops' clockwise is clockwise in the font's y-up coordinates
        total += c.area * (-1 if c.clockwise else 1)
    return sign * total - pathops.simplify(path).area


def flattened(drawing, flat=FLAT):
    """The closed polylines ((n, 2) arrays) of a recording pen's drawing, each within
    ``flat`` of its curves."""
    pen = _FlatteningPen(flat)
    drawing.replay(pen)
    return pen.contours


def glyph_overlaps(name, drawing, flat=FLAT):
    """:class:`GlyphOverlaps` of one glyph (a recording pen's drawing)."""
    contours = flattened(drawing, flat)
    sign = 1 if sum(_signed_area(c) for c in contours) >= 0 else -1
    return GlyphOverlaps(name, len(contours), polygon_overlaps(contours, sign, flat),
                         pathops_excess(drawing, sign) if contours else 0.0)


def font_overlaps(path, names=None, flat=FLAT):
    """[:class:`GlyphOverlaps`] of every glyph (or ``names``) of a written font."""
    return [glyph_overlaps(n, d, flat) for n, d in font_glyphs(path, names)]

"""One fontTools pen for both font readers: it records contours, the readers decide.

(:func:`draw_paths` goes the other way: paths of polynomial pieces onto any pen.)

:func:`record_contours` draws with a :class:`fontTools.pens.basePen.BasePen` subclass
that only *records*: each contour becomes a :class:`RawContour` (its pieces, exactly as
drawn, its start point and whether it was closed).  What a contour means is left to the
caller, as pure functions on the records: a filled glyph (:mod:`.glyphs`) refuses open
contours and closes the others, a skeleton (:mod:`.ufo`) keeps them open and turns a
lone point into a dot.

Contract (BasePen): ``_moveTo``, ``_lineTo``, ``_curveToOne`` and ``_qCurveToOne`` are
overridden; BasePen splits TrueType quadratic runs at their implied on-curve points and
long cubic runs, and decomposes components through the glyph set it was given
(``glyph_set=None``: components are refused with a ParseError).  A ``moveTo`` while a
contour is pending ends that contour as open.
"""

from itertools import compress

import numpy as np

from .. import piece as pc
from ..errors import ParseError
from ..limits import MAX_COORDINATE

__all__ = ["RawContour", "record_contours", "record_segments", "closing_line", "draw_paths"]


class RawContour:
    """A contour as drawn: polynomial pieces joined end to start, font units (a plain
    class: processing a dataclass costs every process about half a ms)."""

    def __init__(self, pieces, start, closed):
        self.pieces, self.start, self.closed = pieces, start, closed

    def __repr__(self):
        return "RawContour(start=%r, closed=%r)" % (self.start, self.closed)


def closing_line(contour):
    """The contour's pieces with a line back to its start added when the last piece
    ends elsewhere (what ``closePath`` means)."""
    pieces = list(contour.pieces)
    if pieces and not np.array_equal(pc.end(pieces[-1]), contour.start):
        pieces.append(pc.line(pc.end(pieces[-1]), contour.start))
    return pieces


_PEN_CLASS = None


def _pen_class():
    """The recording BasePen subclass (built on first use: fontTools loads lazily)."""
    global _PEN_CLASS
    if _PEN_CLASS is not None:
        return _PEN_CLASS
    from fontTools.pens.basePen import BasePen

    class RecordingPen(BasePen):
        """Segment pen -> ``self.contours``, a list of :class:`RawContour`."""

        def __init__(self, glyph_set, label, raw=False):
            super().__init__(glyph_set)
            self.contours = []
            self.label = label
            self.raw = raw
            self._pieces = None
            self._start = None

        def _moveTo(self, pt):
            self._finish(closed=False)
            self._pieces = []
            self._start = pt if self.raw else np.asarray(pt, float)

        def _add(self, points):
            if self.raw:
                self._pieces.append((self._getCurrentPoint(),) + tuple(points))
            else:
                self._pieces.append(pc.from_points([self._getCurrentPoint()] + list(points)))

        def _lineTo(self, pt):
            self._add([pt])

        def _curveToOne(self, pt1, pt2, pt3):
            self._add([pt1, pt2, pt3])

        def _qCurveToOne(self, pt1, pt2):
            self._add([pt1, pt2])

        def _closePath(self):
            self._finish(closed=True)

        def _endPath(self):
            self._finish(closed=False)

        def addComponent(self, glyphName, transformation):
            if self.glyphSet is None:
                raise ParseError("%s: components are read by component_paths" % self.label,
                                 self.label)
            super().addComponent(glyphName, transformation)

        def _finish(self, closed):
            if self._pieces is not None:
                self.contours.append(RawContour(self._pieces, self._start, bool(closed)))
            self._pieces, self._start = None, None

    _PEN_CLASS = RecordingPen
    return RecordingPen


def record_contours(draw, label, glyph_set=None):
    """The :class:`RawContour` list that ``draw(pen)`` draws.

    ``label`` names the glyph in error messages; ``glyph_set`` decomposes components
    (None: a component raises ParseError).

    Raises:
        ParseError: a non-finite point or one beyond ``MAX_COORDINATE``; what ``draw``
            raises as ParseError.
    """
    pen = _pen_class()(glyph_set, label)
    draw(pen)
    pen._finish(closed=False)  # a contour drawn without closePath/endPath
    for c in pen.contours:
        _check_coordinates(np.concatenate([np.ravel(c.start)] + [np.ravel(p) for p in c.pieces]),
                           label)
    return pen.contours


def record_segments(draw, label, glyph_set=None):
    """:func:`record_contours` without the arrays: each contour as a
    :class:`RawContour` whose ``pieces`` are the segments' points as drawn (tuples of
    (x, y), the segment's start first: 2 for a line, 3 for a quadratic, 4 for a
    cubic) and whose ``start`` is the (x, y) of its ``moveTo``; a caller reading many
    glyphs builds all their pieces at once (:func:`morph.parse.read_glyphs`).

    Raises:
        ParseError: as :func:`record_contours`.
    """
    pen = _pen_class()(glyph_set, label, raw=True)
    draw(pen)
    pen._finish(closed=False)
    for c in pen.contours:  # in record_contours' order: the same error first
        _check_coordinates(np.array([c.start] + [p for seg in c.pieces for p in seg], float),
                           label)
    return pen.contours


def _check_coordinates(pts, label):
    if not np.all(np.isfinite(pts)):
        raise ParseError("%s has a non-finite point" % label, label)
    if np.max(np.abs(pts)) > MAX_COORDINATE:
        raise ParseError("%s has a coordinate of %.3g; morph computes with |coordinates| "
                         "up to %g" % (label, np.max(np.abs(pts)), MAX_COORDINATE), label)


def draw_paths(pen, paths):
    """Draw paths ``(pieces, closed)`` of polynomial pieces (lines, quadratics, cubics,
    joined end to start) on a fontTools segment pen: ``moveTo``, then ``lineTo`` /
    ``qCurveTo`` / ``curveTo`` per piece, then ``closePath`` or ``endPath``.

    Raises:
        ValueError: a rational piece or one of degree above 3.
    """
    for pieces, closed in paths:
        if not len(pieces):
            continue
        pts = [pc.cartesian(p) for p in pieces]
        pen.moveTo(tuple(pts[0][0]))
        for p, q in zip(pieces, pts):
            if not pc.is_polynomial(p) or len(q) > 4:
                raise ValueError("only lines, quadratics and cubics can be drawn on a pen")
            points = [tuple(v) for v in q[1:]]
            if len(q) == 2:
                pen.lineTo(points[0])
            elif len(q) == 3:
                pen.qCurveTo(*points)
            else:
                pen.curveTo(*points)
        if closed:
            pen.closePath()
        else:
            pen.endPath()


def glyph_loops(groups, n_pieces, contour, n_contours, bad=None):
    """Per glyph its loops, from the pieces of many glyphs built at once: ``groups``
    of :class:`morph.piece.Pieces` (rows, stack) over ``n_pieces`` pieces in drawing
    order, ``contour`` each piece's contour, ``n_contours`` each glyph's contours in
    order.  Pieces of zero length are dropped, then contours left empty; a glyph
    flagged in ``bad`` gives None (the pen draws it).  The decoders of glyph bytes
    (:mod:`morph.parse.truetype`, :mod:`morph.parse.charstrings`) end here."""
    from ..region import zero_length_mask

    pieces = pc.Pieces([g for g in groups if len(g[0])], n_pieces)
    keep = ~zero_length_mask(pieces) if n_pieces else np.zeros(0, bool)
    owner = np.asarray(contour, np.int64)[keep]
    rows = list(compress(pieces.rows(), keep.tolist()))
    if (np.diff(owner) < 0).any():    # pieces not in contour order (the decoders' are)
        order = np.argsort(owner, kind="stable")
        rows, owner = [rows[k] for k in order.tolist()], owner[order]
    # each contour's pieces, a slice of the kept rows
    ends = np.cumsum(np.bincount(owner, minlength=int(np.sum(n_contours)))).tolist()
    loops = [rows[a:b] for a, b in zip([0] + ends[:-1], ends)]
    out, c = [], 0
    for g, n in enumerate(np.asarray(n_contours).tolist()):
        out.append(None if bad is not None and bad[g] else
                   [loop for loop in loops[c:c + n] if loop])
        c += n
    return out

"""A glyph's integer contours as three arrays (:class:`Outline`): what the font
writers encode (:mod:`morph.fonts.stream`), what :func:`morph.fonts.tables.
integer_outlines` makes of certified cubics or quadratics, and what
:func:`morph.parse.charstrings.charstring_outlines` reads from a font's charstrings.
It depends on numpy alone, so the readers and the writers share it without importing
each other.
"""

import numpy as np


class Outline:
    """A glyph's integer contours held as three arrays, the form the font writers
    encode without drawing point by point (:func:`morph.fonts.stream.compile_outline`).

    ``points``: (P, 2) float array of integer values: each contour's start point,
    then each of its segments' points after the first (its last segment ends on the
    start point, repeated); ``sizes``: per segment the number of points after its
    first (1 line, 2 quadratic, 3 cubic, more: a TrueType spline); ``counts``: per
    contour its number of segments.  It is also the sequence of contours of
    :func:`clean_contour` (each a list of ``(k, 2)`` arrays, views of ``points``),
    so every consumer of those lists takes it.
    """

    __slots__ = ("points", "sizes", "counts")

    def __init__(self, points, sizes, counts):
        self.points = np.asarray(points, float).reshape(-1, 2)
        self.sizes = np.asarray(sizes, np.int64).reshape(-1)
        self.counts = np.asarray(counts, np.int64).reshape(-1)

    @classmethod
    def from_contours(cls, contours):
        """The outline of contours given as lists of segments (an :class:`Outline`
        as it is)."""
        if isinstance(contours, Outline):
            return contours
        points, sizes, counts = [], [], []
        for segs in contours:
            segs = [np.asarray(q, float) for q in segs]
            if not segs:
                continue
            points.append(segs[0][:1])
            for q in segs:
                points.append(q[1:])
                sizes.append(len(q) - 1)
            counts.append(len(segs))
        return cls(np.concatenate(points) if points else np.zeros((0, 2)), sizes, counts)

    def __getstate__(self):
        return self.points, self.sizes, self.counts

    def __setstate__(self, state):
        self.points, self.sizes, self.counts = state

    def __len__(self):
        return len(self.counts)

    def __bool__(self):
        return len(self.counts) > 0

    def segment_starts(self):
        """Index in ``points`` of each segment's first point."""
        contour_of = np.repeat(np.arange(len(self.counts)), self.counts)
        return np.cumsum(self.sizes) - self.sizes + contour_of

    def point_count(self):
        """The number of points of the contours as fonts count them (a contour's
        closing point once)."""
        return len(self.points) - len(self.counts)

    def _segments(self, starts, at, n):
        return [self.points[a:a + m + 1]
                for a, m in zip(starts[at:at + n].tolist(), self.sizes[at:at + n].tolist())]

    def __getitem__(self, k):
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        n = len(self.counts)
        k = k + n if k < 0 else k
        if not 0 <= k < n:
            raise IndexError("contour index out of range")
        return self._segments(self.segment_starts(), int(self.counts[:k].sum()),
                              int(self.counts[k]))

    def __iter__(self):
        starts, at = self.segment_starts(), 0
        for n in self.counts.tolist():
            yield self._segments(starts, at, n)
            at += n

    def __eq__(self, other):
        """Equal to an outline, or to contour lists, with the same segments."""
        if not isinstance(other, (Outline, list, tuple)):
            return NotImplemented
        return len(other) == len(self) and all(
            len(a) == len(b) and all(np.array_equal(p, q) for p, q in zip(a, b))
            for a, b in zip(self, other))

    __hash__ = None

    def __repr__(self):
        return "Outline(%d contours, %d points)" % (len(self), self.point_count())

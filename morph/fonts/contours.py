"""Integer contours drawn on a fontTools pen (:func:`draw_contours`): the contours
:func:`morph.fonts.tables.contours_from_loops` makes and the workers send back, drawn
by the table writers (:mod:`morph.fonts.tables`) and compiled by the streaming
compiler (:mod:`morph.fonts.stream`), so it stands below both.
"""

from ..errors import MorphError

__all__ = ["draw_contours"]

def draw_contours(pen, contours, quadratic):
    """Draw integer contours (see :func:`morph.fonts.tables.contours_from_loops`) on a
    fontTools pen.

    Each contour starts at its first point; its last segment ends there, and a
    closing line is left to ``closePath`` (no repeated point).
    """
    for segs in contours:
        pen.moveTo(tuple(int(v) for v in segs[0][0]))
        last = len(segs) - 1
        for k, s in enumerate(segs):
            pts = [tuple(int(v) for v in q) for q in s[1:]]
            if len(s) == 2:
                if k < last:  # the closing line is implied by closePath
                    pen.lineTo(pts[0])
            elif quadratic and len(s) >= 3:
                pen.qCurveTo(*pts)      # a quadratic, or a spline (on-curves implied)
            elif len(s) == 4:
                pen.curveTo(*pts)
            else:
                raise MorphError("cannot draw a %d-point segment in a %s font"
                                 % (len(s), "TrueType" if quadratic else "CFF"))
        pen.closePath()

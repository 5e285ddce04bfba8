"""Stored glyf glyphs read from their headers: what ``maxp.recalc`` and the glyph
boxes need of a simple glyph (contours, box, points) without decoding its points
(:class:`Header`), the compiled glyphs lent to a composite's bounds
(:class:`Expanded`, :class:`HeaderFont`), and ufo2ft's glyph boxes from them
(:func:`glyf_boxes`).

Shared by the stored-outline compilers of ufo2ft (:mod:`morph.fonts.stored`), the
static compiler (:mod:`morph.fonts.tables_static`) and the table writers
(:mod:`morph.fonts.tables`); it imports nothing of morph.
"""

import struct
from collections import namedtuple

__all__ = ["Header", "Expanded", "HeaderFont", "Box", "glyf_boxes"]

class Header:
    """What ``maxp.recalc`` and the boxes read of a stored simple glyph, from its
    bytes without decoding its points: the header (contours, box) and the number
    of points (the last contour's end + 1)."""

    def __init__(self, data):
        self.numberOfContours, self.xMin, self.yMin, self.xMax, self.yMax = \
            struct.unpack(">hhhhh", data[:10])
        n = self.numberOfContours
        self.points = struct.unpack(">H", data[8 + 2 * n:10 + 2 * n])[0] + 1

    def getMaxpValues(self):
        return self.points, self.numberOfContours

    def isComposite(self):
        return False


class Expanded(dict):
    """The compiled glyphs as a glyf table lends them to a composite's bounds and
    maxp values: a stored glyph as a :class:`Header` (``headers``) or a decoded
    copy (``headers=False``), the stored bytes left as they are."""

    def __init__(self, glyphs, headers=True):
        super().__init__(glyphs)
        self.headers = headers

    def __getitem__(self, name):
        from fontTools.ttLib.tables._g_l_y_f import Glyph

        g = dict.__getitem__(self, name)
        if not hasattr(g, "data"):
            return g
        if self.headers:
            return Header(g.data)
        g = Glyph(g.data)
        g.expand(None)
        return g


class HeaderFont:
    """The font as ``maxp.recalc`` reads it, its glyf table :class:`Expanded`."""

    def __init__(self, otf, glyf):
        self.otf, self.glyf = otf, glyf

    def __getitem__(self, tag):
        return self.glyf if tag == "glyf" else self.otf[tag]

    def getGlyphOrder(self):
        return self.otf.getGlyphOrder()


Box = namedtuple("BoundingBox", ["xMin", "yMin", "xMax", "yMax"])


def glyf_boxes(compiled, box_type):
    """ufo2ft's glyph boxes of the compiled glyf glyphs ``compiled`` (name -> glyph),
    as ``box_type`` (None for an empty glyph): a stored glyph's from its header, the
    others' recomputed (a composite's from its bases, stored ones decoded apart)."""
    boxes = {}
    decoded = Expanded(compiled, headers=False)
    for name, g in compiled.items():
        if hasattr(g, "data"):
            g = Header(g.data)
        else:
            g.recalcBounds(decoded)
        box = box_type(g.xMin, g.yMin, g.xMax, g.yMax)
        boxes[name] = None if box == (0, 0, 0, 0) else box
    return boxes

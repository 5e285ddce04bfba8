"""The pieces of a CFF 1 table that the writers of CFF fonts share, below all of them:

- a charstring's advance (:func:`width_prefix`, :data:`_NO_WIDTHS`) and the Private
  dict's default and nominal widths (:func:`optimize_widths`, fontTools' rule);
- charstrings that answer ``calcBounds`` with the bounds computed where they were
  compiled (:func:`BoundedCharString`, :func:`as_bounded`, :func:`bounded_t2_pen`,
  :func:`bound_charstrings`), so that a save does not decompile them;
- ufo2ft's subroutinizing of a whole font by cffsubr's ``tx`` (:func:`subroutinize`);
- the byte encodings of a CFF INDEX (:func:`_index`, :func:`_index_head`) and of
  dict entries (:class:`_CffDictWriter`).

The streaming compiler (:mod:`morph.fonts.stream`) and its ufo2ft compilers
(:mod:`morph.fonts.stored`), the grouped subroutinizer (:mod:`morph.fonts.subrs`),
the table writers (:mod:`morph.fonts.tables`) and the static compiler
(:mod:`morph.fonts.tables_static`) all use them; it imports nothing of morph, and
fontTools, cffsubr and numpy only where a function runs.
"""

import struct
from types import SimpleNamespace

__all__ = ["width_prefix", "optimize_widths", "BoundedCharString", "as_bounded",
           "is_bounded", "bounded_t2_pen", "bound_charstrings", "subroutinize",
           "NOT_FOR_TX"]

#: the private dict a charstring without an advance is drawn with
_NO_WIDTHS = SimpleNamespace(defaultWidthX=0, nominalWidthX=0)


def width_prefix(width, default, nominal):
    """The bytes a Type 2 charstring starts with for an advance ``width`` (nothing for
    the font's ``default`` width; else ``width - nominal``), as ``T2CharStringPen``
    writes it."""
    from fontTools.misc.psCharStrings import encodeIntT2
    from fontTools.misc.roundTools import otRound

    if width == default:
        return b""
    return encodeIntT2(otRound(width - nominal))


def _t2():
    from fontTools.misc.psCharStrings import T2CharString

    return T2CharString


class _BoundedMixin:
    bounds = None

    def calcBounds(self, glyphSet):
        return self.bounds


def _bounded_class():
    global _BOUNDED
    if _BOUNDED is None:
        _BOUNDED = type("BoundedCharString", (_BoundedMixin, _t2()), {"__doc__": (
            "A charstring whose bounds were computed where it was compiled (the worker: "
            "``calcBounds`` of the same program): fontTools asks a CFF font's charstrings "
            "for their bounds for the font box, head and hhea on every save, which would "
            "decompile each one in Python.")})
    return _BOUNDED


_BOUNDED = None


def BoundedCharString(*args, **kwargs):  # noqa: N802 - a class made on first use
    """A T2 charstring answering ``calcBounds`` with its ``bounds`` (see
    :func:`_bounded_class`)."""
    return _bounded_class()(*args, **kwargs)


def as_bounded(cs, bounds):
    """``cs`` made a bounded charstring with ``bounds``."""
    cs.__class__ = _bounded_class()
    cs.bounds = bounds
    return cs


def is_bounded(cs):
    return _BOUNDED is not None and isinstance(cs, _BOUNDED)


#: the tables the subroutinizer's save leaves out (:func:`subroutinize`): layout
#: tables, which read no other table and are the most costly to compile
NOT_FOR_TX = frozenset(("GDEF", "GPOS", "GSUB"))


def subroutinize(otf, bounds):
    """ufo2ft's subroutinizing of a CFF 1 font (cffsubr's ``tx``, which saves the
    whole font), given the font without its layout tables (:data:`NOT_FOR_TX`; ``tx``
    reads the CFF and cmap tables): they would be compiled only to be compiled
    again when the font is saved.  The other tables are the font's own, so that the
    save sets their boxes and metrics as ufo2ft's does.  The new charstrings then
    answer ``calcBounds`` with ``bounds`` (glyph name -> the bounds of its
    charstring as compiled: the same paths)."""
    import cffsubr
    from fontTools.ttLib import TTFont

    rest = TTFont(sfntVersion=otf.sfntVersion, recalcBBoxes=otf.recalcBBoxes,
                  recalcTimestamp=otf.recalcTimestamp)
    rest.setGlyphOrder(otf.getGlyphOrder())
    for tag in otf.keys():
        if tag != "GlyphOrder" and tag not in NOT_FOR_TX:
            rest[tag] = otf[tag]
    cffsubr.subroutinize(rest, cff_version=1, keep_glyph_names=False)
    otf["CFF "] = rest["CFF "]
    bound_charstrings(otf, bounds)


def bound_charstrings(otf, bounds):
    """The CFF charstrings of ``otf`` (plain ones) answer ``calcBounds`` with
    ``bounds``."""
    if "CFF " not in otf or not bounds:
        return
    t2 = _t2()
    charstrings = otf["CFF "].cff.topDictIndex[0].CharStrings
    for name in otf.getGlyphOrder():
        if name in bounds and name in charstrings:
            cs = charstrings[name]
            if type(cs) is t2:
                as_bounded(cs, bounds[name])


#: a Type 2 charstring's width operand (the advance less nominalWidthX) costs 1 byte
#: up to ONE_BYTE_WIDTH from zero, 2 up to TWO_BYTE_WIDTH, else 5
#: (fontTools.cffLib.width's byte costs)
ONE_BYTE_WIDTH, TWO_BYTE_WIDTH = 107, 1131
#: the nearest widths 2 and 5 bytes away from the nominal width
NEAR, FAR = ONE_BYTE_WIDTH + 1, TWO_BYTE_WIDTH + 1


def optimize_widths(widths):
    """(default, nominal): the CFF Private dict's ``defaultWidthX`` and
    ``nominalWidthX`` of fontTools' ``optimizeWidths`` (fontTools.cffLib.width, the
    widths ufo2ft chooses) for the glyph advances ``widths`` (ints), by its rule on
    arrays over the range of the advances: its running sums and maxima of the advances'
    counts (up and down) are cumulative sums and maxima, its cost of each nominal
    width one array (the first cheapest wins, as ``min`` picks), its candidates for
    the default (the starts of the runs of equal maxima it walks back) found by
    searching the monotone maxima.  fontTools computes the same with a Python call per
    advance of the range (a few ms a font, the range being about an em)."""
    import numpy as np

    w = np.asarray(widths, dtype=np.int64)
    lo = int(w.min())
    counts = np.bincount(w - lo)
    n, total, top = len(counts), int(counts.sum()), int(counts.max())
    up_sum, up_max = np.cumsum(counts), np.maximum.accumulate(counts)
    down_sum = np.cumsum(counts[::-1])[::-1]
    down_max = np.maximum.accumulate(counts[::-1])[::-1]

    def up(arr, beyond, shift):    # arr at domain index + shift; 0 below, beyond above
        k = np.arange(n) + shift
        return np.where(k < 0, 0, np.where(k >= n, beyond, arr[np.clip(k, 0, n - 1)]))

    def down(arr, beyond, shift):  # 0 above, beyond below
        k = np.arange(n) + shift
        return np.where(k >= n, 0, np.where(k < 0, beyond, arr[np.clip(k, 0, n - 1)]))

    nominal_cost = (up(up_sum, total, 0) + up(up_sum, total, -NEAR)
                    + 3 * up(up_sum, total, -FAR) + down(down_sum, total, 0)
                    + down(down_sum, total, NEAR) + 3 * down(down_sum, total, FAR) - counts)
    default_up = np.maximum.reduce([up(up_max, top, 0), 2 * up(up_max, top, -NEAR),
                                    5 * up(up_max, top, -FAR)])
    default_down = np.maximum.reduce([down(down_max, top, 0), 2 * down(down_max, top, NEAR),
                                      5 * down(down_max, top, FAR)])
    saving = np.maximum(default_up, default_down)
    k = int(np.argmin(nominal_cost - saving))
    return _best_default(counts, lo, k, up_max, down_max, saving[k] == default_up[k]), lo + k


def _best_default(counts, lo, k, up_max, down_max, upward):
    """:func:`optimize_widths`' default width for the nominal width ``lo + k``: of the
    three runs of equal maxima ending at the nominal width and at NEAR and FAR from it
    (below it where the saving came from the running maxima upward, else above), the
    run's far end that costs the fewest bytes, the first of equal ones."""
    import numpy as np

    n, nominal = len(counts), lo + k
    ends = []
    for step in (0, NEAR, FAR):
        start = nominal - step if upward else nominal + step
        i = start - lo
        if upward:   # the maxima upward: 0 below the range, nondecreasing in it
            ends.append(start if i < 0 else
                        lo + int(np.searchsorted(up_max, up_max[min(i, n - 1)])))
        else:        # the maxima downward: 0 above the range, nonincreasing in it
            ends.append(start if i >= n else
                        lo + int(np.count_nonzero(down_max >= down_max[max(i, 0)])) - 1)
    gap = np.abs(np.arange(lo, lo + n) - nominal)
    cost = np.where(gap <= ONE_BYTE_WIDTH, 1, np.where(gap <= TWO_BYTE_WIDTH, 2, 5))
    paid = counts * cost
    whole = int(paid.sum())
    return min(ends, key=lambda d: whole - (int(paid[d - lo]) if 0 <= d - lo < n else 0))


def _index_head(sizes):
    """The count, offset size and offsets of a CFF INDEX of items of ``sizes`` bytes
    (what comes before the items' data)."""
    import numpy as np

    if not len(sizes):
        return b"\0\0"
    ends = np.concatenate([[1], 1 + np.cumsum(sizes, dtype=np.int64)])
    last = int(ends[-1])
    size = 1 if last < 1 << 8 else 2 if last < 1 << 16 else 3 if last < 1 << 24 else 4
    offsets = ends.astype(">u4").view(np.uint8).reshape(-1, 4)[:, 4 - size:]
    return struct.pack(">HB", len(sizes), size) + offsets.tobytes()


def _index(items):
    """A CFF INDEX of the byte strings ``items``."""
    if not items:
        return b"\0\0"
    ends = [1]
    for item in items:
        ends.append(ends[-1] + len(item))
    size = 1 if ends[-1] < 1 << 8 else 2 if ends[-1] < 1 << 16 else 3 if ends[-1] < 1 << 24 \
        else 4
    return (struct.pack(">HB", len(items), size)
            + b"".join(e.to_bytes(size, "big") for e in ends) + b"".join(items))


class _CffDictWriter:
    """CFF dict entries as bytes, with the custom strings they name (SIDs from 391,
    in order of first use)."""

    def __init__(self):
        self.strings = {}

    def sid(self, text):
        return 391 + self.strings.setdefault(text, len(self.strings))

    @staticmethod
    def entry(op, *values):
        from fontTools.misc.psCharStrings import encodeFloat, encodeIntCFF

        return b"".join(encodeFloat(v) if isinstance(v, float) else encodeIntCFF(int(v))
                        for v in values) + bytes(op)

    def text(self, op, value):
        from fontTools.misc.psCharStrings import encodeIntCFF

        return encodeIntCFF(self.sid(value)) + bytes(op)

    @staticmethod
    def offset(op, *values):
        """Fixed-size numbers: the dict's length does not move with them."""
        return b"".join(b"\x1d" + struct.pack(">l", v) for v in values) + bytes(op)


def bounded_t2_pen(*args, **kwargs):
    """fontTools' ``T2CharStringPen`` that also draws the points it writes (rounded
    as it rounds them) into a ``BoundsPen`` (its ``bounds``): the calls the
    charstring's ``calcBounds`` would make, from its decoded program, give the same
    bounds."""
    global _BOUNDED_PEN
    if _BOUNDED_PEN is None:
        from fontTools.pens.boundsPen import BoundsPen
        from fontTools.pens.t2CharStringPen import T2CharStringPen

        class BoundedT2Pen(T2CharStringPen):
            def __init__(self, *args, **kwargs):
                super().__init__(*args, **kwargs)
                self.bounds = BoundsPen(None)

            def _rounded(self, pt):
                return self.round(pt[0]), self.round(pt[1])

            def _moveTo(self, pt):
                super()._moveTo(pt)
                self.bounds.moveTo(self._rounded(pt))

            def _lineTo(self, pt):
                super()._lineTo(pt)
                self.bounds.lineTo(self._rounded(pt))

            def _curveToOne(self, pt1, pt2, pt3):
                super()._curveToOne(pt1, pt2, pt3)
                self.bounds.curveTo(self._rounded(pt1), self._rounded(pt2),
                                    self._rounded(pt3))

            def _closePath(self):
                super()._closePath()
                self.bounds.closePath()

            def _endPath(self):
                super()._endPath()
                self.bounds.endPath()

        _BOUNDED_PEN = BoundedT2Pen
    return _BOUNDED_PEN(*args, **kwargs)


_BOUNDED_PEN = None

"""Type 2 charstrings (CFF) read into outline arrays without fontTools' pens.

fontTools draws a charstring by decompiling it into a program (a Python list of
numbers and operator names) and running that program against a pen, one method
call a point; a font's save asks every glyph it did not write for its bounds that
way.  :func:`charstring_outlines` reads the bytes once, operand by operand, into the
arrays of :class:`morph.outline.Outline` (absolute points, segment sizes,
contour counts), so that :func:`morph.fonts.stream.outline_bounds` computes the
boxes of all glyphs at once, with the arithmetic of fontTools' ``BoundsPen``.

What is read: every path operator of the Type 2 format (moveto, lines, the
curve shorthands, flex), stem hints and hint masks (skipped, their stems counted
for the mask lengths), the advance width operand (dropped), local and global
subroutines.  A charstring using anything else (the arithmetic and storage
operators, ``seac``-style ``endchar``, CFF2's ``blend``) or a coordinate that is
not an integer (16.16 operands) gives None: the caller draws that glyph with
fontTools.  Tests: tests/fonts/test_charstrings.py (against fontTools' drawing and
``calcBounds`` on hinted, subroutinized fonts and on every operator).
"""

import numpy as np

from ..outline import Outline

__all__ = ["charstring_outlines", "cff_glyph_loops"]

_STEMS = (1, 3, 18, 23)             # hstem, vstem, hstemhm, vstemhm
_MASKS = (19, 20)                   # hintmask, cntrmask
_STACK_CLEARING = {1: 2, 3: 2, 18: 2, 23: 2, 19: 2, 20: 2,   # operand pairs
                   21: 2, 22: 1, 4: 1, 14: 0}                # moveto, endchar


class _Unread(Exception):
    """A charstring the arrays do not take (see the module's docstring)."""


def _bias(subrs):
    n = len(subrs)
    return 107 if n < 1240 else 1131 if n < 33900 else 32768


def _operand(code, pos, b0):
    """(value, next position) of the number starting with byte ``b0``."""
    if b0 <= 246:
        return b0 - 139, pos + 1
    if b0 <= 250:
        return (b0 - 247) * 256 + code[pos + 1] + 108, pos + 2
    if b0 <= 254:
        return -(b0 - 251) * 256 - code[pos + 1] - 108, pos + 2
    value = int.from_bytes(code[pos + 1:pos + 5], "big", signed=True)
    if value & 0xFFFF:
        raise _Unread("a 16.16 operand")
    return value >> 16, pos + 5


class _Path:
    """Absolute points, segment sizes and contour counts as they are read."""

    def __init__(self):
        self.x = self.y = 0
        self.points, self.sizes, self.counts = [], [], []
        self.start = None           # the open contour's start point
        self.first = 0              # its first segment's index

    def move(self, dx, dy):
        self.close()
        self.x += dx
        self.y += dy
        self.start = (self.x, self.y)
        self.points.append(self.start)
        self.first = len(self.sizes)

    def line(self, dx, dy):
        if self.start is None:
            self.move(0, 0)
        self.x += dx
        self.y += dy
        self.points.append((self.x, self.y))
        self.sizes.append(1)

    def curve(self, dx1, dy1, dx2, dy2, dx3, dy3):
        if self.start is None:
            self.move(0, 0)
        x1, y1 = self.x + dx1, self.y + dy1
        x2, y2 = x1 + dx2, y1 + dy2
        self.x, self.y = x2 + dx3, y2 + dy3
        self.points += [(x1, y1), (x2, y2), (self.x, self.y)]
        self.sizes.append(3)

    def close(self):
        """End the open contour (a closing line where it ends off its start)."""
        if self.start is None:
            return
        if len(self.sizes) == self.first:
            raise _Unread("a contour of a moveto alone")
        if (self.x, self.y) != self.start:
            self.points.append(self.start)
            self.sizes.append(1)
        self.counts.append(len(self.sizes) - self.first)
        self.start = None


def _alternating(path, args, horizontal):
    """hlineto / vlineto."""
    for a in args:
        path.line(a, 0) if horizontal else path.line(0, a)
        horizontal = not horizontal


def _hv_curves(path, args, horizontal):
    """hvcurveto / vhcurveto: curves starting horizontal or vertical by turns, the
    last one taking a fifth operand when there is one."""
    while len(args) >= 4:
        a, b, c, d = args[:4]
        args = args[4:]
        last = args[0] if len(args) == 1 else 0
        if len(args) == 1:
            args = []
        if horizontal:
            path.curve(a, 0, b, c, last, d)
        else:
            path.curve(0, a, b, c, d, last)
        horizontal = not horizontal
    if args:
        raise _Unread("a curve shorthand with stray operands")


def _same_curves(path, args, horizontal):
    """hhcurveto / vvcurveto."""
    lead = 0
    if len(args) % 4:
        lead, args = args[0], args[1:]
    for k in range(0, len(args) - 3, 4):
        a, b, c, d = args[k:k + 4]
        if horizontal:
            path.curve(a, lead, b, c, d, 0)
        else:
            path.curve(lead, a, b, c, 0, d)
        lead = 0


def _flex(path, op, a):
    """The flex operators (12 35, 34, 36, 37) as their two curves."""
    if op == 35 and len(a) == 13:
        path.curve(*a[:6])
        path.curve(*a[6:12])
    elif op == 34 and len(a) == 7:
        path.curve(a[0], 0, a[1], a[2], a[3], 0)
        path.curve(a[4], 0, a[5], -a[2], a[6], 0)
    elif op == 36 and len(a) == 9:
        path.curve(a[0], a[1], a[2], a[3], a[4], 0)
        path.curve(a[5], 0, a[6], a[7], a[8], -(a[1] + a[3] + a[7]))
    elif op == 37 and len(a) == 11:
        dx, dy = sum(a[0:10:2]), sum(a[1:10:2])
        last = (a[10], -dy) if abs(dx) > abs(dy) else (-dx, a[10])
        path.curve(*a[:6])
        path.curve(*a[6:10], *last)
    else:
        raise _Unread("escape operator 12 %d" % op)


def _draw(path, op, args):
    """One path operator (its operands with the advance removed)."""
    if op == 21:
        path.move(args[0], args[1])
    elif op == 22:
        path.move(args[0], 0)
    elif op == 4:
        path.move(0, args[0])
    elif op == 5:
        for k in range(0, len(args) - 1, 2):
            path.line(args[k], args[k + 1])
    elif op in (6, 7):
        _alternating(path, args, op == 6)
    elif op == 8:
        for k in range(0, len(args) - 5, 6):
            path.curve(*args[k:k + 6])
    elif op == 24:
        for k in range(0, len(args) - 7, 6):
            path.curve(*args[k:k + 6])
        path.line(*args[-2:])
    elif op == 25:
        for k in range(0, len(args) - 7, 2):
            path.line(args[k], args[k + 1])
        path.curve(*args[-6:])
    elif op in (26, 27):
        _same_curves(path, args, op == 27)
    elif op in (30, 31):
        _hv_curves(path, args, op == 31)
    else:
        raise _Unread("operator %d" % op)


class _Reader:
    """One charstring's interpreter state: the operand stack, the hints counted,
    whether the advance operand was met.  As fontTools reads them, only the first
    hint mask takes operands (vstem hints) and fixes the masks' length."""

    def __init__(self, cs):
        private = getattr(cs, "private", None)
        self.subrs = getattr(private, "Subrs", None) or []
        self.gsubrs = getattr(cs, "globalSubrs", None) or []
        self.path = _Path()
        self.stack = []
        self.stems = 0
        self.mask_bytes = None      # the hint masks' length, set at the first
        self.width_done = False

    def _args(self, op):
        """The operands of a stack-clearing ``op``, the advance dropped where it
        leads them (only the first such operator may carry it)."""
        args, self.stack = self.stack, []
        if not self.width_done:
            self.width_done = True
            per = _STACK_CLEARING[op]
            if (per == 2 and len(args) % 2) or (per == 1 and len(args) == 2) or (
                    per == 0 and len(args) in (1, 5)):
                args = args[1:]
        return args

    def _call(self, subrs, calls):
        index = self.stack.pop() + _bias(subrs)
        if not 0 <= index < len(subrs) or len(calls) > 10:
            raise _Unread("a subroutine call out of range")
        return _program_bytes(subrs[index])

    def read(self, code):
        """The path of the charstring ``code`` (bytes)."""
        calls, pos, end, stack = [], 0, len(code), self.stack
        while True:
            if pos >= end:
                if not calls:
                    break
                code, pos = calls.pop()
                end = len(code)
                continue
            b0 = code[pos]
            if 32 <= b0 <= 246:         # most operands: one byte
                stack.append(b0 - 139)
                pos += 1
            elif b0 >= 32:
                value, pos = _operand(code, pos, b0)
                stack.append(value)
            elif b0 == 28:
                stack.append(int.from_bytes(code[pos + 1:pos + 3], "big", signed=True))
                pos += 3
            elif b0 in (10, 29):
                target = self._call(self.subrs if b0 == 10 else self.gsubrs, calls)
                calls.append((code, pos + 1))
                code, pos, end = target, 0, len(target)
            elif b0 == 11:
                code, pos = calls.pop() if calls else (code, end)
                end = len(code)
            elif b0 == 14:
                if self._args(14):
                    raise _Unread("endchar as seac")
                break
            else:
                pos = self._operator(code, pos, b0)
                stack = self.stack
        self.path.close()
        return self.path

    def _operator(self, code, pos, op):
        """Run the operator at ``pos`` (not a number, call, return or endchar);
        the position after it."""
        if op in _STEMS:
            self.stems += len(self._args(op)) // 2
            return pos + 1
        if op in _MASKS:
            if self.mask_bytes is None:     # operands of the first mask: vstems
                self.stems += len(self._args(op)) // 2
                self.mask_bytes = (self.stems + 7) // 8
            return pos + 1 + self.mask_bytes
        if op == 12:
            _flex(self.path, code[pos + 1], self.stack)
            self.stack = []
            return pos + 2
        args = self._args(op) if op in _STACK_CLEARING else self.stack
        self.stack = []
        _draw(self.path, op, args)
        return pos + 1


def _program_bytes(cs):
    if cs.bytecode is None:
        cs.compile()
    return cs.bytecode


def charstring_outlines(charstrings):
    """[:class:`morph.outline.Outline` or None] of fontTools ``T2CharString``
    objects: each glyph's path read from its bytes (a charstring decompiled
    already is compiled first); None where the charstring uses what the module's
    docstring lists as unread."""
    out = []
    for cs in charstrings:
        try:
            path = _Reader(cs).read(_program_bytes(cs))
        except (_Unread, IndexError, TypeError, ValueError):
            out.append(None)
            continue
        points = np.array(path.points, float).reshape(-1, 2)
        out.append(Outline(points, path.sizes, path.counts))
    return out


def cff_glyph_loops(font, names):
    """Per name: the closed loops (lists of pieces, weights 1) of the glyph of the
    static CFF ``font`` as :func:`morph.parse.glyphs.read_glyphs` draws them (a line
    per line, a cubic per curve, pieces of zero length dropped, a closing line where
    a contour ends off its start, contours left empty dropped), [] for a glyph
    without contours, or None for a glyph left to the pen (not in the font, or a
    charstring :func:`charstring_outlines` does not read)."""
    charstrings = font["CFF "].cff.topDictIndex[0].CharStrings
    present = [k for k, n in enumerate(names) if n in charstrings]
    outlines = charstring_outlines([charstrings[names[k]] for k in present])
    out = [None] * len(names)
    read = [(k, o) for k, o in zip(present, outlines) if o is not None]
    for (k, _), loops in zip(read, _outline_loops([o for _, o in read])):
        out[k] = loops
    return out


def _outline_loops(outlines):
    """The loops of :class:`morph.outline.Outline` s of lines and cubics, the
    pieces of all built at once (:func:`morph.parse.pens.glyph_loops`); per outline
    its loops."""
    from .pens import glyph_loops

    if not outlines:
        return []
    sizes = np.concatenate([o.sizes for o in outlines])
    counts = np.concatenate([o.counts for o in outlines])
    pts = np.concatenate([o.points for o in outlines])
    contour = np.repeat(np.arange(len(counts)), counts)
    first = np.cumsum(sizes) - sizes + contour       # each segment's first point
    groups = []
    for size in (1, 3):
        ks = np.flatnonzero(sizes == size)
        if len(ks):
            h = np.ones((len(ks), size + 1, 3))
            h[:, :, :2] = pts[first[ks, None] + np.arange(size + 1)]
            groups.append((ks, h))
    return glyph_loops(groups, len(sizes), contour, [len(o.counts) for o in outlines])

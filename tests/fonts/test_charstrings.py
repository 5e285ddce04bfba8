"""morph.parse.charstrings: Type 2 charstrings read into outline arrays, checked
against fontTools drawing the same charstrings (its pen's points, in order) and
against ``calcBounds`` (fontTools' ``BoundsPen``)."""

import copy
import io
from types import SimpleNamespace

import numpy as np
import pytest
from fontTools.misc.psCharStrings import T2CharString
from fontTools.pens.recordingPen import RecordingPen
from fontTools.ttLib import TTFont

from morph.fonts.stream import outline_bounds
from morph.parse import cubic_test_font_path
from morph.parse.charstrings import _outline_loops, cff_glyph_loops, charstring_outlines

#: a private dict without subroutines, advances counted from 0
NO_WIDTHS = SimpleNamespace(nominalWidthX=0, defaultWidthX=0)


def _drawn(cs, glyph_set=None):
    """fontTools' path of ``cs``: per contour its points (start, then each
    segment's points), the closing line made explicit as the reader writes it."""
    pen = RecordingPen()
    cs.draw(pen)
    contours, current = [], None
    for op, args in pen.value:
        if op == "moveTo":
            current = [tuple(args[0])]
        elif op in ("lineTo", "curveTo"):
            current += [tuple(p) for p in args]
        else:
            if current[-1] != current[0]:
                current.append(current[0])
            contours.append(current)
    return contours


def _read(outline):
    """The reader's path in the form of :func:`_drawn`."""
    pts = outline.points.tolist()
    contours, at, seg = [], 0, 0
    for n in outline.counts.tolist():
        size = int(outline.sizes[seg:seg + n].sum())
        contours.append([tuple(p) for p in pts[at:at + size + 1]])
        at, seg = at + size + 1, seg + n
    return contours


def _font_charstrings(font):
    top = font["CFF "].cff.topDictIndex[0]
    return [top.CharStrings[n] for n in font.getGlyphOrder()], top.CharStrings


def _check_font(font):
    items, charstrings = _font_charstrings(font)
    outlines = charstring_outlines(items)
    assert all(o is not None for o in outlines)
    for cs, outline in zip(items, outlines):
        assert _read(outline) == _drawn(copy.copy(cs))
    bounds = outline_bounds(outlines)
    ref = [copy.copy(cs).calcBounds(charstrings) for cs in items]
    assert bounds == ref
    return outlines


def test_bundled_font_read_as_fonttools_draws_it():
    outlines = _check_font(TTFont(cubic_test_font_path()))
    assert sum(len(o.sizes) for o in outlines) > 2000


def test_subroutinized_font_read_as_fonttools_draws_it():
    """The bundled font subroutinized by cffsubr (local subroutines)."""
    import cffsubr

    font = TTFont(cubic_test_font_path())
    cffsubr.subroutinize(font)
    buf = io.BytesIO()
    font.save(buf)
    font = TTFont(io.BytesIO(buf.getvalue()))
    top = font["CFF "].cff.topDictIndex[0]
    assert len(top.Private.Subrs) > 10
    _check_font(font)


def test_global_and_nested_subroutines():
    """A charstring calling a global subroutine that calls a local one (bias 107)."""
    local = [T2CharString(program=[30, 40, "rlineto", "return"])]
    glob = [T2CharString(program=[10, 20, "rlineto", -107, "callsubr", "return"])]
    for sub in local + glob:
        sub.compile()
    private = SimpleNamespace(Subrs=local, nominalWidthX=0, defaultWidthX=0)
    cs = T2CharString(program=[5, 5, "rmoveto", -107, "callgsubr", 1, 1, "rlineto",
                               "endchar"], private=private, globalSubrs=glob)
    cs.compile()
    outline = charstring_outlines([cs])[0]
    assert _read(outline) == [[(5, 5), (15, 25), (45, 65), (46, 66), (5, 5)]]
    assert _read(outline) == _drawn(cs)


#: programs for every path operator, hints, masks, the advance operand and flex
PROGRAMS = [
    [100, 10, 20, "rmoveto", 30, 40, 50, -60, "rlineto", 5, 6, 7, 8, 9, 10, "rrcurveto",
     "endchar"],
    [7, 20, 30, 40, "hstemhm", 5, 10, 60, 20, "hintmask", bytes([0xC0]), 10, 20, "rmoveto",
     30, 40, -30, "hlineto", "cntrmask", bytes([0xF0]), 20, 15, 25, 35, "vlineto",
     "hintmask", bytes([0x30]), 5, 5, "rlineto", "endchar"],
    [12, "hmoveto", 1, 2, 3, 4, 5, 6, 7, 8, "hhcurveto", 9, 1, 2, 3, 4, 5, 6, 7, 8,
     "vvcurveto", 4, "vmoveto", 1, 2, 3, 4, 5, 6, 7, 8, 9, "hvcurveto", 1, 2, 3, 4, 5,
     6, 7, 8, "vhcurveto", "endchar"],
    [0, 0, "rmoveto", 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, "rcurveline",
     1, 2, 3, 4, 5, 6, 7, 8, 9, 10, "rlinecurve", 1, 2, 3, 4, 5, "hvcurveto", "endchar"],
    [50, "vstem", 10, 10, "rmoveto", 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 50, "flex",
     1, 2, 3, 4, 5, 6, 7, "hflex", 1, 2, 3, 4, 5, 6, 7, 8, 9, "hflex1",
     1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, "flex1", 1, 20, 3, 4, 5, 6, 7, 8, 9, -10, 11,
     "flex1", "endchar"],
    [99, "endchar"],
    ["endchar"],
]


@pytest.mark.parametrize("program", PROGRAMS)
def test_every_operator_read_as_fonttools_draws_it(program):
    cs = T2CharString(program=program)
    cs.compile()
    outline = charstring_outlines([cs])[0]
    assert outline is not None
    assert _read(outline) == _drawn(T2CharString(bytecode=cs.bytecode, private=NO_WIDTHS))
    drawn = T2CharString(bytecode=cs.bytecode, private=NO_WIDTHS)
    assert outline_bounds([outline]) == [drawn.calcBounds({})]


def test_the_comparison_sees_a_point_moved():
    """The check above fails on a path one unit off at one point."""
    cs = T2CharString(program=PROGRAMS[2])
    cs.compile()
    outline = charstring_outlines([cs])[0]
    outline.points[5, 1] += 1
    assert _read(outline) != _drawn(T2CharString(bytecode=cs.bytecode, private=NO_WIDTHS))


@pytest.mark.parametrize("program", [
    [0, 0, "rmoveto", 1.5, 2, "rlineto", "endchar"],          # a 16.16 operand
    [0, 10, 20, 65, 66, "endchar"],                           # seac
    [0, 0, "rmoveto", 1, 2, "add", 3, "rlineto", "endchar"],  # arithmetic
    [10, 10, "rmoveto", 20, 20, "rmoveto", 5, 5, "rlineto", "endchar"],  # a lone moveto
])
def test_what_is_not_read_gives_none(program):
    cs = T2CharString(program=program)
    cs.compile()
    assert charstring_outlines([cs]) == [None]


def test_a_brushed_cff_font_keeps_its_unwritten_glyphs_bounds(tmp_path):
    """``morph brush`` on the CFF font: the glyphs it did not write keep the
    boxes fontTools computes (hmtx side bearings, the CFF font box)."""
    from morph.fonts import brush

    out = tmp_path / "out.otf"
    brush.brush_font(str(cubic_test_font_path()), str(out), brush.ellipse_nib(40, 10, 30),
                     ["A", "o"], tol=0.5, jobs=1)
    font = TTFont(str(out))
    items, charstrings = _font_charstrings(font)
    boxes = np.array([b for b in (copy.copy(cs).calcBounds(charstrings) for cs in items)
                      if b is not None])
    top = font["CFF "].cff.topDictIndex[0]
    assert list(top.FontBBox) == [int(np.floor(boxes[:, 0].min())),
                                  int(np.floor(boxes[:, 1].min())),
                                  int(np.ceil(boxes[:, 2].max())),
                                  int(np.ceil(boxes[:, 3].max()))]


def _same_loops(a, b):
    return len(a) == len(b) and all(
        len(p) == len(q) and all(np.array_equal(x, y) for x, y in zip(p, q))
        for p, q in zip(a, b))


def test_cff_glyph_loops_are_the_pens():
    """Every glyph of the bundled CFF font, and of it subroutinized: the loops
    read from the bytes are those read_glyphs gets drawing on its pen, value for
    value (pieces, order, zero-length pieces dropped, closing lines); a name not in
    the font is left to the pen."""
    import cffsubr

    from morph.parse import glyphs as G

    for subroutinized in (False, True):
        font = TTFont(cubic_test_font_path())
        if subroutinized:
            cffsubr.subroutinize(font)
        names = font.getGlyphOrder()
        got = cff_glyph_loops(font, names + ["nosuchglyph"])
        gs = font.getGlyphSet()
        drawn = G._filled_loops([G._glyph_segments(gs, n, n, "test") for n in names], names)
        assert got[-1] is None
        assert all(_same_loops(a, b) for a, b in zip(got, drawn))
        assert sum(1 for loops in got if loops) > 150


def test_cff_glyph_loops_drop_zero_length_pieces_and_close():
    """A repeated point (zero-length line and curve dropped) and a contour ending
    off its start (closing line), against the pen."""
    from morph.parse import glyphs as G

    program = [0, 0, "rmoveto", 100, 0, "rlineto", 0, 0, "rlineto", 0, 0, 0, 0, 0, 0,
               "rrcurveto", 0, 100, 10, 10, -10, 10, "rrcurveto", 50, 50, "rmoveto",
               10, 0, 0, 10, "rlineto", -10, -10, "rlineto", "endchar"]
    cs = T2CharString(program=program, private=NO_WIDTHS)
    cs.compile()
    loops = _outline_loops(charstring_outlines([cs]))[0]
    drawn = G._filled_loops([G._glyph_segments({"g": _GlyphOf(cs)}, "g", "g", "t")],
                            ["g"])[0]
    assert [len(loop) for loop in loops] == [3, 3]   # closing line added to the first only
    assert _same_loops(loops, drawn)


class _GlyphOf:
    def __init__(self, cs):
        self.draw = cs.draw


def test_unwritten_glyphs_bounds_read_by_batches(monkeypatch):
    """The bounds of the glyphs a brush does not write, read a few glyphs at a time,
    are those of one batch and those fontTools computes."""
    import morph.fonts.tables as tables

    ref = TTFont(cubic_test_font_path())
    items, charstrings = _font_charstrings(ref)
    want = [copy.copy(cs).calcBounds(charstrings) for cs in items]
    calls = []
    import morph.parse.charstrings as reader

    def counted(batch):
        calls.append(len(batch))
        return charstring_outlines(batch)

    monkeypatch.setattr(reader, "charstring_outlines", counted)
    monkeypatch.setattr(tables, "BOUNDS_BATCH", 50)
    font = TTFont(cubic_test_font_path())
    tables.outline_writer(font).saving()
    got = [cs.bounds for cs in _font_charstrings(font)[0]]
    assert calls == [50, 50, 50, len(items) - 150]
    assert got == want

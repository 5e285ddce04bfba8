"""morph.fonts.variable_cff2: a glyph whose blended CFF2 charstring is longer than a
reader takes is written as a run of local subroutine calls.

The font is built through the brush's CFF2 writer (``write_cff2`` with the brush's
own plan of masters) from a synthetic glyph: a wavy ring of 400 cubics, jittered
at each of 41 masters along wght, so every coordinate carries 40 nonzero deltas
(about 100 KB of charstring; Source Serif 4's e with a 60 x 15 nib needs 154
masters and 334 KB)."""

import numpy as np
import pytest

from morph.errors import MorphError
from morph.fonts import variable_cff2
from morph.fonts.variable_cff2 import MAX_CHARSTRING, split_long_charstrings, write_cff2
from tests.fontfixtures import finish_tables

#: masters along wght and cubics of the synthetic glyph "e"
MASTERS, CUBICS = 41, 400
#: instance locations compared (the axis' ends, its default, between masters)
WGHTS = (100.0, 262.5, 400.0, 537.5, 900.0)


def _font(split=True, masters=MASTERS, cubics=CUBICS):
    """A CFF2 font of .notdef, o (3 masters: the wght grid) and e (``masters``
    masters, its own VarData chosen by vsindex; a ring of ``cubics``), written by
    ``write_cff2``;
    ``split`` False writes e's charstring whole (the program the split one must
    draw)."""
    from fontTools.fontBuilder import FontBuilder
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    from morph.fonts.variable_brush import _Plan

    fb = FontBuilder(1000, isTTF=True)
    names = [".notdef", "o", "e"]
    fb.setupGlyphOrder(names)
    fb.setupCharacterMap({0x6F: "o", 0x65: "e"})
    fb.setupGlyf({n: TTGlyphPen(None).glyph() for n in names})
    finish_tables(fb, names, "Split", 600, 800, -200)
    fb.setupFvar([("wght", 100, 400, 900, "Weight")], [])
    grid = [{}, {"wght": -1.0}, {"wght": 1.0}]
    locs = grid + [{"wght": float(v)} for v in np.linspace(-1, 1, masters)
                   if abs(v) > 1e-9 and abs(v) != 1.0]
    plan = _Plan(None, [None], [(60, 15, 30)], locs, len(grid),
                 {"e": [0] + sorted(range(1, len(locs)), key=lambda k: locs[k]["wght"])},
                 ["wght"])
    rng = np.random.default_rng(35)
    t = np.linspace(0.0, 2 * np.pi, 3 * cubics + 1)

    def ring(w, radius, jitter):
        r = radius + 40 * w + 30 * np.sin(7 * t + w)
        pts = np.c_[350 + r * np.cos(t), 350 + r * np.sin(t)]
        pts = pts + rng.uniform(-jitter, jitter, pts.shape)
        pts[-1] = pts[0]
        return [np.stack([pts[0:-1:3], pts[1::3], pts[2::3], pts[3::3]], axis=1)]

    results = [(".notdef", None, 0.0)]
    for name, radius, jitter in (("o", 200, 0.0), ("e", 300, 3.0)):
        ms = plan.masters(name)
        results.append((name, [ring(loc.get("wght", 0.0), radius, jitter)
                               for loc in ms.locs], 0.0))
    if split:
        write_cff2(fb.font, plan, results, {}, lambda s, n: 600)
    else:
        real = variable_cff2.split_long_charstrings
        variable_cff2.split_long_charstrings = lambda font: {}
        try:
            write_cff2(fb.font, plan, results, {}, lambda s, n: 600)
        finally:
            variable_cff2.split_long_charstrings = real
    return fb.font


def _saved(font, path):
    from fontTools.ttLib import TTFont

    font.save(str(path))
    return TTFont(str(path))


def _drawn(path, wght, instance):
    """The recorded outline of e at ``wght``: drawn from fontTools' instancer's
    static font (``instance``) or from the variable font's glyph set there."""
    from fontTools.pens.recordingPen import RecordingPen
    from fontTools.ttLib import TTFont
    from fontTools.varLib import instancer

    font = TTFont(str(path))
    if instance:
        glyphs = instancer.instantiateVariableFont(font, {"wght": wght}).getGlyphSet()
    else:
        glyphs = font.getGlyphSet(location={"wght": wght})
    pen = RecordingPen()
    glyphs["e"].draw(pen)
    return pen.value


def test_long_blended_charstring_is_split_into_subroutines(tmp_path):
    """e's blended program (over 65,535 bytes: the unsplit font is what ots and the
    readers refuse) becomes ``vsindex`` and a run of callsubr; the charstrings
    and subroutines are each within 65,535 bytes, ots-sanitize passes, and
    fontTools' instancer and its blend evaluation draw exactly the unsplit
    program's outline at every location (the comparison can fail: two locations
    differ)."""
    import ots  # a test extra: missing, the test fails rather than skips
    whole = _saved(_font(split=False), tmp_path / "Whole.otf")
    e = whole["CFF2"].cff.topDictIndex[0].CharStrings["e"]
    assert len(e.bytecode) > MAX_CHARSTRING
    assert ots.sanitize(str(tmp_path / "Whole.otf"), capture_output=True).returncode != 0

    font = _saved(_font(), tmp_path / "Split.otf")
    top = font["CFF2"].cff.topDictIndex[0]
    subrs = top.FDArray[0].Private.Subrs
    sizes = [len(top.CharStrings[n].bytecode) for n in font.getGlyphOrder()]
    assert len(subrs) >= 2 and max(sizes) <= MAX_CHARSTRING
    assert all(len(s.bytecode) <= MAX_CHARSTRING for s in subrs)
    assert sum(len(s.bytecode) for s in subrs) > MAX_CHARSTRING
    e = top.CharStrings["e"]
    e.decompile()
    bias = 107
    assert e.program == [1, "vsindex"] + [t for k in range(len(subrs))
                                           for t in (k - bias, "callsubr")]
    r = ots.sanitize(str(tmp_path / "Split.otf"), capture_output=True)
    assert r.returncode == 0, r.stderr
    for instance in (True, False):
        drawn = {w: _drawn(tmp_path / "Split.otf", w, instance) for w in WGHTS}
        for w in WGHTS:
            assert drawn[w] == _drawn(tmp_path / "Whole.otf", w, instance), (w, instance)
        assert drawn[WGHTS[0]] != drawn[WGHTS[1]]


def test_what_cannot_be_split_is_refused(monkeypatch):
    """One clear line where no split fits: more parts than a Private dict addresses,
    or one path operator longer than a subroutine may be (limits shrunk here; at
    65,535 bytes and 65,536 subroutines neither happens below 4 GB)."""
    font = _font(split=False)
    with pytest.raises(MorphError, match="glyph 'e' has a curve of .* blended bytes"):
        split_long_charstrings(font, limit=200)
    monkeypatch.setattr(variable_cff2, "MAX_SUBRS", 1)
    with pytest.raises(MorphError, match="subroutines of split charstrings, more than "
                                         "the 1"):
        split_long_charstrings(_font(split=False), limit=MAX_CHARSTRING)


def test_more_masters_than_a_blend_takes_are_refused(tmp_path):
    """A glyph of 509 masters cannot be blended within CFF2's operand stack (513):
    one line naming it and pointing to .ttf; 507, the most, passes ots."""
    import ots  # a test extra: missing, the test fails rather than skips
    with pytest.raises(MorphError, match="glyph 'e' needs 509 masters, more than the 507 "
                                         "a CFF2 blend takes .* TrueType"):
        _font(masters=509, cubics=4)
    _saved(_font(masters=variable_cff2.MAX_BLEND_MASTERS, cubics=4), tmp_path / "Most.otf")
    r = ots.sanitize(str(tmp_path / "Most.otf"), capture_output=True)
    assert r.returncode == 0, r.stderr


def test_an_operator_longer_than_a_subroutine_is_made_one_per_curve(tmp_path):
    """The specializer joins curves into one operator up to 513 blended operands,
    which with many masters can pass what a subroutine holds: such an operator is
    written one per curve (here with the limit shrunk to 4,000 bytes, below the
    synthetic e's longest operator), drawing the same outline."""
    from fontTools.ttLib import TTFont

    import ots  # a test extra: missing, the test fails rather than skips
    _saved(_font(split=False), tmp_path / "Whole.otf")
    font = TTFont(str(tmp_path / "Whole.otf"))
    whole = font["CFF2"].cff.topDictIndex[0].CharStrings["e"]
    whole.decompile()
    curves = whole.program.count("rrcurveto")
    assert "e" in split_long_charstrings(font, limit=4000)
    font = _saved(font, tmp_path / "Small.otf")
    private = font["CFF2"].cff.topDictIndex[0].FDArray[0].Private
    assert max(len(s.bytecode) for s in private.Subrs) <= 4000
    for s in private.Subrs:
        s.private = private             # a subroutine read alone needs it for its blends
        s.decompile()
    assert sum(s.program.count("rrcurveto") for s in private.Subrs) > curves
    r = ots.sanitize(str(tmp_path / "Small.otf"), capture_output=True)
    assert r.returncode == 0, r.stderr
    for w in WGHTS:
        assert _drawn(tmp_path / "Small.otf", w, False) == \
            _drawn(tmp_path / "Whole.otf", w, False), w

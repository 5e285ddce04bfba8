"""morph.fonts.tables (contour clean-up, anchors, names), checked on hand-made cases."""

from pathlib import Path

import numpy as np
import pytest
from fontTools.ttLib import TTFont

from morph.fonts.tables import clean_contour, move_anchors, rename_family
from morph.parse import default_font_path
from tests.fontfixtures import build_mark_font

A = np.array


def _pts(contour):
    """The contour's points in order (end points once)."""
    out = [tuple(contour[0][0])]
    for s in contour:
        out.extend(tuple(p) for p in s[1:])
    return out[:-1]


def test_clean_contour_removes_defects():
    square = [A([[0, 0], [100, 0]]), A([[100, 0], [100, 0.2]]),  # zero length once rounded
              A([[100, 0.2], [100, 50]]), A([[100, 50], [100, 100]]),  # collinear: merged
              A([[100, 100], [50, 100.4], [0, 100]]),  # quad with a collinear control: kept
              A([[0, 100], [0, 100], [0, 0]])]  # control on the start: a line
    c = clean_contour(square)
    pts = _pts(c)
    assert len(set(pts)) == len(pts)  # no repeated point
    assert [len(s) for s in c] == [2, 2, 3, 2]
    assert all(float(v).is_integer() for s in c for v in s.ravel())
    for a, b in zip(c, c[1:] + c[:1]):
        assert tuple(a[-1]) == tuple(b[0])  # still a closed chain


def test_clean_contour_spike_and_retracted_handles():
    spike = [A([[0, 0], [100, 0]]), A([[100, 0], [101, 2]]), A([[101, 2], [100, 0]]),
             A([[100, 0], [100, 100]]), A([[100, 100], [0, 0]])]
    c = clean_contour(spike)
    ends = [(tuple(s[0]), tuple(s[-1])) for s in c]
    assert ((100.0, 0.0), (101.0, 2.0)) not in ends and len(c) == 3
    cubic = [A([[0, 0], [0, 0], [50, 80], [100, 0]]), A([[100, 0], [0, 0]])]
    c = clean_contour(cubic)
    assert len(c[0]) == 4 and tuple(c[0][1]) != (0.0, 0.0)  # handle moved one unit
    assert np.abs(c[0][1] - [0, 0]).max() == 1
    tiny = [A([[413, 102], [413, 101], [412, 101], [412, 101]]), A([[412, 101], [0, 0]]),
            A([[0, 0], [413, 102]])]
    c = clean_contour(tiny)
    assert [len(s) for s in c] == [2, 2, 2]  # a 1-unit cubic is its chord
    assert clean_contour([A([[0, 0], [10, 0]]), A([[10, 0], [0, 0]])]) == []


def test_move_anchors_by_glyph(tmp_path):
    """Base anchors of e move, mark anchors of acutecomb move, o's stay; format 2
    anchors (contour points) become format 1."""
    font = TTFont(str(build_mark_font(tmp_path / "m.ttf")))
    gpos = font["GPOS"].table
    st = [s for lk in gpos.LookupList.Lookup for s in lk.SubTable
          if type(s).__name__ == "MarkBasePos"][0]
    base = dict(zip(st.BaseCoverage.glyphs, st.BaseArray.BaseRecord))
    marks = dict(zip(st.MarkCoverage.glyphs, st.MarkArray.MarkRecord))
    e0 = base["e"].BaseAnchor[0].XCoordinate, base["e"].BaseAnchor[0].YCoordinate
    o0 = base["o"].BaseAnchor[0].XCoordinate
    m0 = marks["acutecomb"].MarkAnchor.YCoordinate
    base["e"].BaseAnchor[0].Format = 2
    base["e"].BaseAnchor[0].AnchorPoint = 3
    n = move_anchors(font, {"e": (40, -3), "acutecomb": (0, 7)})
    assert n >= 3
    a = base["e"].BaseAnchor[0]
    assert (a.XCoordinate, a.YCoordinate, a.Format) == (e0[0] + 40, e0[1] - 3, 1)
    assert not hasattr(a, "AnchorPoint")
    assert base["o"].BaseAnchor[0].XCoordinate == o0
    assert marks["acutecomb"].MarkAnchor.YCoordinate == m0 + 7
    font.save(str(tmp_path / "n.ttf"))  # still compiles


def _extension_mark_font(path):
    """The mark test font with its mark-to-base lookup behind an extension lookup."""
    from fontTools.feaLib.builder import addOpenTypeFeaturesFromString

    font = TTFont(str(build_mark_font(path.with_name("marks.ttf"))))
    del font["GPOS"]
    addOpenTypeFeaturesFromString(font, """
    markClass [acutecomb] <anchor 0 500> @TOP;
    lookup Ext useExtension { pos base [e o] <anchor 300 700> mark @TOP; } Ext;
    feature mark { lookup Ext; } mark;
    """)
    font.save(str(path))
    return path


@pytest.mark.parametrize("build", ["marks", "extension"])
def test_anchors_move_in_a_stored_gpos(tmp_path, build):
    """A GPOS read from the file (not decompiled before): its mark-to-base lookup
    is found in the stored bytes (behind an extension lookup too) and e's anchor
    moves; o's stays."""
    path = (build_mark_font(tmp_path / "m.ttf") if build == "marks"
            else _extension_mark_font(tmp_path / "x.ttf"))
    font = TTFont(str(path))
    assert not font.isLoaded("GPOS")
    before = TTFont(str(path))
    assert move_anchors(font, {"e": (40, -3)}) >= 1
    font.save(str(tmp_path / "n.ttf"))
    after = TTFont(str(tmp_path / "n.ttf"))

    def base_anchors(f):
        subtables = [s.ExtSubTable if hasattr(s, "ExtSubTable") else s
                     for lk in f["GPOS"].table.LookupList.Lookup for s in lk.SubTable]
        st = [s for s in subtables if type(s).__name__ == "MarkBasePos"][0]
        return {g: (r.BaseAnchor[0].XCoordinate, r.BaseAnchor[0].YCoordinate)
                for g, r in zip(st.BaseCoverage.glyphs, st.BaseArray.BaseRecord)}
    was, now = base_anchors(before), base_anchors(after)
    assert now["e"] == (was["e"][0] + 40, was["e"][1] - 3) and now["o"] == was["o"]


def test_gpos_without_anchors_is_left_as_stored(tmp_path):
    """The bundled font's GPOS (kerning only) and GDEF (no carets) are not
    decompiled to move anchors, and the save writes their stored bytes; the mark
    font's GPOS (anchors) is decompiled, its GDEF (no carets) is not."""
    font = TTFont(default_font_path())
    assert move_anchors(font, {"A": (40, 0), "V": (10, 0)}) == 0
    assert not font.isLoaded("GPOS") and not font.isLoaded("GDEF")
    font.save(str(tmp_path / "n.ttf"))
    saved, source = TTFont(str(tmp_path / "n.ttf")), TTFont(default_font_path())
    for tag in ("GPOS", "GDEF", "GSUB", "name"):
        assert saved.reader[tag] == source.reader[tag], tag
    marks = TTFont(str(build_mark_font(tmp_path / "m.ttf")))
    move_anchors(marks, {"e": (40, 0)})
    assert marks.isLoaded("GPOS") and not marks.isLoaded("GDEF")


def test_ligature_carets_move_in_a_stored_gdef(tmp_path):
    """A GDEF with a ligature caret list (read from the file) is decompiled and the
    caret of a moved ligature moves in x."""
    from fontTools.feaLib.builder import addOpenTypeFeaturesFromString

    font = TTFont(default_font_path())
    addOpenTypeFeaturesFromString(font, "table GDEF { LigatureCaretByPos f 300; } GDEF;")
    font.save(str(tmp_path / "c.ttf"))
    font = TTFont(str(tmp_path / "c.ttf"))
    move_anchors(font, {"f": (25, 0)})
    lig = font["GDEF"].table.LigCaretList
    assert lig.Coverage.glyphs == ["f"] and lig.LigGlyph[0].CaretValue[0].Coordinate == 325


@pytest.mark.parametrize("style, want", [
    ("Regular", {1: "X Brush", 2: "Regular", 4: "X Brush Regular", 6: "XBrush-Regular",
                 16: None, 17: None}),
    ("SemiBold Italic", {1: "X Brush SemiBold", 2: "Italic", 4: "X Brush SemiBold Italic",
                         6: "XBrush-SemiBoldItalic", 16: "X Brush", 17: "SemiBold Italic"}),
])
def test_rename_family(style, want):
    font = TTFont(default_font_path())
    font["name"].setName(style, 17, 3, 1, 0x409)
    font["name"].setName("Old Family", 16, 3, 1, 0x409)
    ps = rename_family(font, "X Brush", tool="t")
    name = font["name"]
    for nid, text in want.items():
        assert name.getDebugName(nid) == text, nid
    assert ps == want[6] and name.getDebugName(3).endswith(";t;" + ps)
    assert name.getDebugName(25) == "XBrush"  # the bundled font has ID 25
    assert all("Old Family" not in r.toUnicode() for r in name.names)


def test_clean_contour_keeps_splines_and_splits_those_that_round_to_repeats():
    """With ``splines`` a TrueType spline (on, off, off, on) stays one segment after
    rounding; one whose off-curve points round to the same point is written as its
    quadratics with explicit on-curve points (each point rounded once)."""
    from morph.fonts.tables import clean_contour

    spline = np.array([[0.0, 0.0], [10.2, 20.1], [30.4, 19.8], [40.0, 0.0]])
    line = np.array([[40.0, 0.0], [0.0, 0.0]])
    out = clean_contour([spline, line], splines=True)
    assert [len(s) for s in out] == [4, 2]
    assert np.array_equal(out[0], np.round(spline))
    close = np.array([[0.0, 0.0], [10.2, 20.1], [10.4, 19.8], [40.0, 0.0]])   # offs round alike
    out = clean_contour([close, line], splines=True)
    mid = np.round(0.5 * (close[1] + close[2]))                 # the explicit midpoint
    # both quadratics' control points round onto that midpoint: two lines through it
    assert [len(s) for s in out] == [2, 2, 2]
    assert np.array_equal(out[0][1], mid) and np.array_equal(out[1][0], mid)
    # without splines a 4-point segment is a cubic, as before
    assert [len(s) for s in clean_contour([spline, line])] == [4, 2]


def _glyf_cases():
    """Contours as the brush writes them (lists of integer segments closing on their
    start), and those ``TTGlyphPen`` trims or keeps differently."""
    tri = [A([[0, 0], [100, 0]]), A([[100, 0], [50, 80]]), A([[50, 80], [0, 0]])]
    spline = [A([[0, 0], [40, -30], [80, 0]]), A([[80, 0], [120, 40], [90, 90], [40, 60]]),
              A([[40, 60], [10, 40], [0, 0]])]          # ends on a curve: start repeated
    hole = [A([[30, 10], [30, 30]]), A([[30, 30], [60, 10]]), A([[60, 10], [30, 10]])]
    two = [A([[5, 5], [9, 9]]), A([[9, 9], [5, 5]])]       # two points
    back = [A([[0, 0], [50, 0]]), A([[50, 0], [0, 0]]), A([[0, 0], [0, 0]])]  # ends on start
    open_curve = [A([[0, 0], [40, 40], [80, 0]]), A([[80, 0], [40, -9], [3, 1]])]  # no close
    return {"lines": [tri], "splines and a hole": [spline, hole], "two points": [two],
            "closing on the start": [tri, back], "curve not closing": [open_curve],
            "empty": []}


def test_truetype_write_many_builds_the_pens_glyphs():
    """write_many (glyphs built from the point arrays) makes the glyphs, bytes and
    lsbs that drawing each with TTGlyphPen (write) makes, the trimmed cases
    included (those are drawn)."""
    from morph.fonts.tables import outline_writer

    cases = _glyf_cases()
    names = ["a", "b", "c", "d", "e", "f"]
    fonts = [TTFont(str(default_font_path())) for _ in range(2)]
    drawn, built = (outline_writer(f) for f in fonts)
    lsb_drawn = [drawn.write(n, c, 500) for n, c in zip(names, cases.values())]
    lsb_built = built.write_many([(n, c, 500) for n, c in zip(names, cases.values())])
    assert lsb_built == lsb_drawn
    for n in names[:3]:   # encoded from the arrays: stored as the bytes the pen's compile
        stored = fonts[1]["glyf"].glyphs[n].data
        assert stored == fonts[0]["glyf"][n].compile(fonts[0]["glyf"]), n
    for n, what in zip(names, cases):
        a, b = fonts[0]["glyf"][n], fonts[1]["glyf"][n]
        assert b.compile(fonts[1]["glyf"]) == a.compile(fonts[0]["glyf"]), what
        assert list(b.coordinates) == list(a.coordinates), what
    assert fonts[1]["glyf"]["b"].numberOfContours == 2
    from morph.fonts.tables import _pen_draws
    from morph.outline import Outline

    draws = _pen_draws([Outline.from_contours(c) for c in cases.values()])
    assert draws == [False, False, False, True, True, True]
    # the check can fail: another outline gives other bytes
    fonts[1]["glyf"]["a"] = fonts[1]["glyf"]["b"]
    assert fonts[1]["glyf"]["a"].compile(fonts[1]["glyf"]) != \
        fonts[0]["glyf"]["a"].compile(fonts[0]["glyf"])


@pytest.mark.parametrize("style", ["Regular", "SemiBold Italic"])
@pytest.mark.parametrize("source", ["NotoSans-Regular.ttf", "NotoSans-Regular.otf"])
def test_renamed_records_are_fonttools(tmp_path, style, source):
    """rename_family of a name table read from its stored records (the bundled
    fonts: Windows Unicode, and Macintosh Roman English in the .otf) writes the bytes
    fontTools' name table writes for the same renaming, and reads the same names."""
    from morph.parse.names import name_records

    path = str(Path(default_font_path()).with_name(source))
    font = TTFont(path)
    font["name"].setName(style, 17, 3, 1, 0x409)
    font.save(str(tmp_path / "s.ttf"))
    light, full = TTFont(str(tmp_path / "s.ttf")), TTFont(str(tmp_path / "s.ttf"))
    assert name_records(light.reader["name"]) is not None
    full["name"].names  # decompiled by fontTools first: its own table renames
    assert rename_family(light, "X Brush", tool="t") == rename_family(full, "X Brush", tool="t")
    assert type(light["name"]).__name__ == "NameTable"
    assert light["name"].compile(light) == full["name"].compile(full)
    for nid in range(30):
        assert light["name"].getDebugName(nid) == full["name"].getDebugName(nid), nid
    light.recalcTimestamp = full.recalcTimestamp = False   # the same head
    light.save(str(tmp_path / "l.ttf"))
    full.save(str(tmp_path / "f.ttf"))
    assert (tmp_path / "l.ttf").read_bytes() == (tmp_path / "f.ttf").read_bytes()


def test_name_table_hands_over_to_fonttools(tmp_path):
    """fontTools' API on a name table held as records (``names``, ``setName``) works
    on fontTools' table of them, which the font then compiles; records in an
    encoding not read here, a format 1 table or a key twice are left to fontTools."""
    import struct

    from morph.parse.names import name_records, name_table

    font = TTFont(default_font_path())
    table = name_table(font, install=True)
    assert table.getDebugName(1) == "Noto Sans"
    table.setName("Other", 1, 3, 1, 0x409)
    assert font["name"].getDebugName(1) == "Other"
    font.save(str(tmp_path / "o.ttf"))
    assert TTFont(str(tmp_path / "o.ttf"))["name"].getDebugName(1) == "Other"

    def table_of(*records, fmt=0):
        head = struct.pack(">3H", fmt, len(records), 6 + 12 * len(records))
        return head + b"".join(struct.pack(">6H", *key, 2, 0) for key in records) + b"\0A"
    assert name_records(table_of((3, 1, 0x409, 1))) == {(3, 1, 0x409, 1): b"\0A"}
    assert name_records(table_of((3, 1, 0x409, 1), fmt=1)) is None
    assert name_records(table_of((3, 1, 0x409, 1), (3, 1, 0x409, 1))) is None
    assert name_records(table_of((1, 0, 5, 1))) is None          # Macintosh, not English
    assert name_records(table_of((3, 3, 0x409, 1))) is None      # Windows PRC

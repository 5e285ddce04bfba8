"""Static fonts compiled without ufo2ft (morph.fonts.tables_static, read by
morph.parse.light_ufo) against ufo2ft.

The reference is ufo2ft compiling the same stroked glyphs (the streamed writer,
:func:`morph.fonts.stream.compile_stored`, itself tested against ufo2ft of the
whole font in test_stream.py): the source read light and read with ufoLib2, each
stroked into .otf and .ttf with the same nib and tolerance.  Every table must be
byte-identical, head but for its time stamps and checksum, except the CFF table:
both are the subroutinizer's (``tx``) output, ufo2ft's re-encoded by fontTools, so
they must be equal as decompiled (their ttx dump).  Sources:

- a Hershey-like skeleton (open lines, a dot, a closed loop, a glyph without
  unicode, a zero-width glyph, minimal font info with a float unitsPerEm), once
  whole and once with only some glyphs chosen (the others empty);
- a CJK-like one (uniXXXX glyphs, one beyond the BMP for cmap 12), rich font info
  (copyright with ©, name records, italic angle, version, fsSelection, panose,
  PostScript widths, gasp ranges, style-map bold italic, non-ASCII names) and a
  feature file (languagesystems, a class, GSUB ligature and single substitution,
  GPOS single and pair adjustments, a GDEF table block);
- the Relief SingleLine subset with what needs ufo2ft's feature writers removed
  (kerning, groups, anchors, composites, production names): real font info.

A source with what the light reader does not take (a data file, an included
feature file) is read by ufoLib2 and compiled by ufo2ft, with the same result as
before.  Kerning, groups, anchors, components, production names and glyphs not
exported: tests/fonts/test_tables_features.py.
"""

import copy
import io

import pytest
import ufoLib2
from fontTools.ttLib import TTFont

from morph.fonts.brush import ellipse_nib
from morph.fonts.stream import SkeletonSource
from morph.fonts.stroke import stroke_ufo
from morph.parse.light_ufo import LightFont
from tests import RELIEF_SUBSET
from tests.fontfixtures import hershey_like, skeleton_line as _line

NIB = (90.0, 20.0, 30.0)


def cjk_like():
    font = ufoLib2.Font()
    info = font.info
    info.familyName, info.styleName = "Kanji Like", "Bold Italic"
    info.styleMapStyleName = "bold italic"
    info.openTypeNamePreferredSubfamilyName = "Bold Italic"
    info.unitsPerEm, info.ascender, info.descender = 1024, 880, -144
    info.copyright = "© 2026 Test Författare"
    info.trademark = "Kanji™ Like"
    info.versionMajor, info.versionMinor = 2, 17
    info.italicAngle = -8.5
    info.openTypeOS2Selection = [7, 8]
    info.openTypeOS2Panose = [2, 11, 5, 2, 4, 5, 4, 2, 2, 4]
    info.openTypeOS2VendorID = "MRPH"
    info.openTypeNameDesigner = "Désigner"
    info.openTypeNameRecords = [dict(nameID=256, platformID=3, encodingID=1,
                                     languageID=0x409, string="Alternate")]
    info.openTypeGaspRangeRecords = [dict(rangeMaxPPEM=8, rangeGaspBehavior=[1, 3]),
                                     dict(rangeMaxPPEM=65535,
                                          rangeGaspBehavior=[0, 1, 2, 3])]
    info.postscriptDefaultWidthX, info.postscriptNominalWidthX = 1024, 700
    info.openTypeHheaAscender, info.openTypeHheaLineGap = 900, 50
    codes = [0x4E00, 0x4E8C, 0x4E09, 0x5341, 0x20000]
    for i, code in enumerate(codes):
        g = font.newGlyph(("uni%04X" if code <= 0xFFFF else "u%05X") % code)
        g.unicodes = [code]
        g.width = 1024
        for k in range(i % 3 + 1):
            _line(g, (100, 200 + 250 * k), (924, 200 + 250 * k + 30 * i))
        if i == 3:
            _line(g, (512, 850), (512, -80))
    font.newGlyph("uni4E00.alt").width = 1024
    _line(font["uni4E00.alt"], (80, 400), (944, 420))
    font.newGlyph("uni4E00_uni4E8C").width = 2048
    _line(font["uni4E00_uni4E8C"], (100, 400), (1900, 400))
    font.features.text = """languagesystem DFLT dflt;
languagesystem hani dflt;
@ONE = [uni4E00 uni4E8C];
feature liga {
    sub uni4E00 uni4E8C by uni4E00_uni4E8C;
} liga;
feature salt {
    sub uni4E00 by uni4E00.alt;
} salt;
feature kern {
    pos uni4E09 -20;
    pos @ONE uni5341 -40;
} kern;
table GDEF {
    GlyphClassDef [uni4E00 uni4E8C uni4E09 uni5341], [uni4E00_uni4E8C], , ;
} GDEF;
"""
    return font


def relief_light():
    font = ufoLib2.Font.open(RELIEF_SUBSET, lazy=False)
    font.kerning.clear()
    font.groups.clear()
    for key in ("public.postscriptNames", "public.skipExportGlyphs"):
        font.lib.pop(key, None)
    for name in [g.name for g in font if g.components]:
        del font[name]
    for g in font:
        g.anchors.clear()
    font.lib["public.glyphOrder"] = [n for n in font.lib["public.glyphOrder"] if n in font]
    font.features.text = ""
    return font


SOURCES = {"hershey": hershey_like, "cjk": cjk_like, "relief": relief_light}


def _ttx(font, tag):
    buf = io.StringIO()
    font.saveXML(buf, tables=[tag])
    return [line for line in buf.getvalue().splitlines() if "ttLibVersion" not in line]


def _same_tables(a_path, b_path):
    """Every table of the two fonts byte-identical, head but for its time stamps
    and checksum, CFF as decompiled."""
    a, b = TTFont(str(a_path)), TTFont(str(b_path))
    assert sorted(a.reader.keys()) == sorted(b.reader.keys())
    for tag in a.reader.keys():
        if tag == "CFF ":
            assert _ttx(a, tag) == _ttx(b, tag), tag
        elif tag != "head":
            assert a.reader[tag] == b.reader[tag], tag
    skip = {"modified", "created", "checkSumAdjustment"}
    assert {k: v for k, v in vars(a["head"]).items() if k not in skip} == \
        {k: v for k, v in vars(b["head"]).items() if k not in skip}
    return a


def _both_ways(ufo_path, out_dir, kind, glyphs=None):
    """(light font, path) and (ufoLib2 font, path) of the UFO at ``ufo_path``
    stroked into ``kind``."""
    done = []
    for light in (True, False):
        source = SkeletonSource(ufo_path, light=light)
        out = out_dir / ("%s%s" % ("light" if light else "ufo2ft", kind))
        stats = stroke_ufo(source, out, ellipse_nib(*NIB), glyphs, tol=0.5, overwrite=True)
        assert not stats["fallback"]
        done.append((source.shell_font(), out))
    return done


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    folder = tmp_path_factory.mktemp("light")
    paths = {}
    for name, make in SOURCES.items():
        paths[name] = folder / ("%s.ufo" % name)
        make().save(paths[name])
    return paths


@pytest.mark.parametrize("kind", [".otf", ".ttf"])
@pytest.mark.parametrize("name,glyphs", [("hershey", None), ("hershey", ["A", "l"]),
                                         ("cjk", None), ("relief", None)])
def test_light_tables_equal_ufo2ft(saved, tmp_path, name, glyphs, kind):
    (light, a), (heavy, b) = _both_ways(saved[name], tmp_path, kind, glyphs)
    assert isinstance(light, LightFont) and not isinstance(heavy, LightFont)
    font = _same_tables(a, b)
    if name == "cjk":
        assert {"GSUB", "GPOS", "GDEF"} <= set(font.keys())
        assert any(t.format == 12 for t in font["cmap"].tables)
        if kind == ".ttf":
            assert font["gasp"].gaspRange == {8: 0b1010, 65535: 0b1111}


@pytest.mark.parametrize("tag", ["OS/2", "CFF "])
def test_a_changed_table_is_seen(saved, tmp_path, tag):
    """The comparison can fail: the same font with one OS/2 field changed, or one
    CFF glyph's program (the XML comparison)."""
    (_, a), _ = _both_ways(saved["hershey"], tmp_path, ".otf")
    font = TTFont(str(a))
    if tag == "OS/2":
        font["OS/2"].usWeightClass += 100
    else:
        cs = font["CFF "].cff.topDictIndex[0].CharStrings["A"]
        cs.decompile()
        cs.program[cs.program.index("rmoveto") - 1] += 1
    font.save(str(tmp_path / "changed.otf"))
    with pytest.raises(AssertionError, match=tag.strip()):
        _same_tables(tmp_path / "changed.otf", a)


def test_light_fonts_pass_ots(saved, tmp_path):
    import ots  # a test extra: missing, the test fails rather than skips

    for kind in (".otf", ".ttf"):
        (_, path), _ = _both_ways(saved["cjk"], tmp_path, kind)
        r = ots.sanitize(str(path), str(tmp_path / ("ots" + kind)), capture_output=True)
        assert r.returncode == 0, r.stderr


def _edited(font, what):
    if what == "data":
        font.data["com.github.fonttools.ttx/x.ttx"] = b"<ttFont/>"
    elif what == "include":
        font.features.text = "include(more.fea);\n"
    return font


@pytest.mark.parametrize("what", ["data", "include"])
def test_what_the_light_reader_leaves_goes_to_ufo2ft(tmp_path, what):
    font = _edited(hershey_like(), what)
    font.save(tmp_path / "s.ufo")
    if what == "include":
        (tmp_path / "more.fea").write_text("feature liga { sub A l by O; } liga;\n")
    source = SkeletonSource(tmp_path / "s.ufo", light=True)
    shells = source.shell_font()
    assert not isinstance(shells, LightFont) and not source.light
    stats = stroke_ufo(source, tmp_path / "s.otf", ellipse_nib(*NIB), None, tol=0.5)
    assert stats["glyphs"] >= 6 and (tmp_path / "s.otf").stat().st_size > 0


def test_info_fallbacks_are_ufo2fts():
    """:func:`morph.fonts.fontinfo.info_value` gives what ufo2ft's
    ``getAttrWithFallback`` gives, for every attribute it has a fallback for, on an
    empty font info and on a rich one (the light reader's info and ufoLib2's)."""
    from ufo2ft.fontInfoData import getAttrWithFallback, specialFallbacks, staticFallbackData

    from morph.fonts.fontinfo import info_value
    from morph.parse.light_ufo import LightInfo

    attrs = sorted(set(staticFallbackData) | set(specialFallbacks))
    for font in (ufoLib2.Font(), cjk_like(), relief_light()):
        values = {a: copy.deepcopy(getattr(font.info, a, None)) for a in attrs}
        light = LightInfo({a: v for a, v in values.items() if v is not None})
        for attr in attrs:
            if attr in ("openTypeHeadCreated",):   # now, to the second
                continue
            expected = getAttrWithFallback(font.info, attr)
            assert info_value(font.info, attr) == expected, attr
            assert info_value(light, attr) == expected, attr


def test_shells_read_light_equal_ufolib2s(saved):
    """The light reader's shells hold what ufoLib2's do: the same glyphs in the same
    order, advances, unicodes, contour counts, lib."""
    for path in saved.values():
        light, heavy = SkeletonSource(path, light=True), SkeletonSource(path)
        a, b = light.shell_font(), heavy.shell_font()
        assert isinstance(a, LightFont) and a.keys() == list(b.keys())
        assert light.contour_counts == heavy.contour_counts
        for name in a.keys():
            ga, gb = a[name], b[name]
            assert (ga.width, ga.height, ga.unicodes, ga.lib) == \
                (gb.width, gb.height, gb.unicodes, dict(gb.lib)), name
        assert a.glyphOrder == b.glyphOrder and a.features.text == (b.features.text or "")



def test_without_cffsubrs_tx_runner_the_cff_table_is_fontTools(saved, tmp_path, monkeypatch):
    """Where cffsubr lacks its runner of ``tx`` on bytes, the CFF table is built with
    fontTools.cffLib and subroutinized through cffsubr's public call: then every
    table is ufo2ft's byte for byte."""
    from morph.fonts import tables_static

    monkeypatch.setattr(tables_static, "_tx_runner", lambda: None)
    (_, a), (_, b) = _both_ways(saved["cjk"], tmp_path, ".otf")
    fa, fb = TTFont(str(a)), TTFont(str(b))
    assert fa.reader["CFF "] == fb.reader["CFF "]
    _same_tables(a, b)


@pytest.mark.parametrize("key,value", [
    ("unitsPerEm", "1000"), ("unitsPerEm", -1000), ("openTypeOS2WidthClass", 12),
    ("styleMapStyleName", "Bold"), ("openTypeOS2Panose", [2, 11]),
    ("openTypeHeadCreated", "yesterday"), ("openTypeOS2Selection", [5]),
    ("postscriptIsFixedPitch", 1), ("openTypeNameRecords", [{"nameID": 1}])])
def test_font_info_ufolib2_refuses_is_refused_as_before(tmp_path, key, value):
    """Font info that ufoLib2's validation refuses is not read light: the source is
    read by ufoLib2, which names the defect (one ParseError) as before."""
    import plistlib

    from morph.errors import ParseError

    hershey_like().save(tmp_path / "s.ufo")
    path = tmp_path / "s.ufo" / "fontinfo.plist"
    info = plistlib.loads(path.read_bytes())
    info[key] = value
    path.write_bytes(plistlib.dumps(info))
    with pytest.raises(ParseError, match="cannot read UFO"):
        SkeletonSource(tmp_path / "s.ufo", light=True).shell_font()
    with pytest.raises(ParseError, match="cannot read UFO"):
        SkeletonSource(tmp_path / "s.ufo")


def test_time_value_reads_dates_as_strptime_does():
    """_time_value's field-by-field reading of ``YYYY/MM/DD HH:MM:SS`` gives what
    ufo2ft's ``time.strptime`` gives (0 where it fails): out-of-range fields,
    29 February, leap seconds, year 0, other forms and digits."""
    import calendar
    import random
    import time

    from morph.fonts.fontinfo import _time_value

    def strptime_value(date):
        try:
            return calendar.timegm(time.strptime(date, "%Y/%m/%d %H:%M:%S"))
        except ValueError:
            return 0

    dates = ["2020/02/29 23:59:60", "2019/02/29 00:00:00", "1900/02/29 00:00:00",
             "0000/01/01 00:00:00", "0001/01/01 00:00:00", "9999/12/31 23:59:61",
             "2020/04/31 00:00:00", "2020/4/30 23:59:59", "2020/04/30  3:59:59",
             "2020-04-30 23:59:59", "\u0662\u0660\u0662\u0660/04/30 23:59:59", ""]
    rng = random.Random(7)
    dates += ["%04d/%02d/%02d %02d:%02d:%02d" % tuple(rng.randint(0, m) for m in
                                                     (9999, 14, 33, 25, 61, 63))
              for _ in range(3000)]
    assert [_time_value(d) for d in dates] == [strptime_value(d) for d in dates]
    assert _time_value("2020/01/02 03:04:05") == 1577934245


def test_optimize_widths_picks_fontTools_widths():
    """optimize_widths' default and nominal widths are fontTools' ``optimizeWidths``
    (what ufo2ft writes) on advances of one em, of several ems (so that widths 108 and
    1132 away count), with negative and repeated advances, ties between candidates
    (few distinct advances, equal counts) and a single advance."""
    import random

    from fontTools.cffLib.width import optimizeWidths

    from morph.fonts.cff_encoding import optimize_widths

    rng = random.Random(11)
    draws = [lambda: rng.randint(0, 1200), lambda: rng.choice([0, 500, 600, 1000, 2500]),
             lambda: rng.randint(-300, 3000), lambda: rng.randint(400, 420),
             lambda: rng.choice(range(0, 5000, 37)),
             lambda: rng.randint(0, 2) * 1132 + rng.randint(0, 108)]
    sets = [[500], [0, 0], [-40, 2300]]
    for k in range(1800):
        sets.append([draws[k % 6]() for _ in range(rng.randint(1, 12 if k % 2 else 300))])
    for widths in sets:
        assert optimize_widths(widths) == optimizeWidths(list(widths)), widths

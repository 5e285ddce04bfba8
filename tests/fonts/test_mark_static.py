"""The mark and mkmk features written without ufo2ft (morph.fonts.mark_static)
against ufo2ft's MarkFeatureWriter: the whole feature file ufo2ft's feature
compiler builds from (its writers' output, recorded in a ufo2ft compile of the
source read by ufoLib2) equals the tree morph writes, written out, character for
character; so feaLib builds the same GPOS and GDEF from both (compared byte for
byte in test_tables_features.py).  Sources cover: bases, marks, marks on marks
(mkmk with mark filtering sets) and ligatures (numbered anchors, a component
without anchors), several mark classes, anchors at fractional coordinates, a
repeated anchor name, unpaired and ignored anchors, glyphs not exported, a
mark class the feature file defines already (at the same anchor, and at
another: a new class), a filtering-set class name the file takes, the mark
feature in the file and mkmk missing, kerning written by the kern writer in the
same file, a Hebrew font (the writer has no direction).  Fonts outside what the
port covers (a GDEF table, contextual anchors, an abvm script, an anchor ufo2ft
refuses) are shown to be left to ufo2ft.
"""

import pytest
import ufoLib2

from tests.fonts.feature_text import ufo2fts, written

BASES = {"A": 0x41, "O": 0x4F, "a": 0x61, "o": 0x6F, "i": 0x69}
MARKS = {"gravecomb": 0x300, "acutecomb": 0x301, "dotbelowcomb": 0x323, "cedillacomb": 0x327}
LATIN_FEA = "languagesystem DFLT dflt;\nlanguagesystem latn dflt;\n"


def _glyph(font, name, code=None, anchors=(), width=500):
    g = font.newGlyph(name)
    g.width = width
    if code is not None:
        g.unicodes = [code]
    for a in anchors:
        g.appendAnchor({"name": a[0], "x": a[1], "y": a[2]})
    return g


def latin(fea=LATIN_FEA, codes=MARKS):
    """Bases with top and bottom anchors, marks (code points ``codes``) with mark
    anchors and top/bottom anchors of their own (mkmk), a ligature with numbered
    anchors."""
    font = ufoLib2.Font()
    font.info.familyName = "Mark Test"
    font.features.text = fea
    for i, (name, code) in enumerate(BASES.items()):
        _glyph(font, name, code, [("top", 250 + i, 700 - i), ("bottom", 250, -10 * i)])
    for name, anchors in (("gravecomb", [("_top", 100, 500), ("top", 100.5, 800)]),
                          ("acutecomb", [("_top", 120.4, 500), ("top", 119.5, 790.5)]),
                          ("dotbelowcomb", [("_bottom", 80, 0), ("bottom", 80, -120)]),
                          ("cedillacomb", [("_bottom", 90, 5)])):
        _glyph(font, name, codes.get(name), anchors, 0)
    _glyph(font, "f_i", 0xFB01, [("top_1", 150, 700), ("top_2", 420, 700),
                                 ("bottom_2", 400, 0)])
    _glyph(font, "f_f_i", 0xFB03, [("top_1", 150, 700), ("_2", 0, 0), ("top_3", 600, 700)])
    _glyph(font, "space", 0x20)
    return font


def all_cases():
    """latin() with: a repeated anchor name (the last counts), unpaired and
    ignored anchors, a glyph not exported, a second mark class of a name with a
    dot, fractional coordinates, a mark glyph with a numbered anchor (skipped)."""
    font = latin()
    font["A"].appendAnchor({"name": "top", "x": 260, "y": 710})
    font["O"].appendAnchor({"name": "center", "x": 300, "y": 350})
    font["O"].appendAnchor({"name": "#note", "x": 1, "y": 1})
    _glyph(font, "hidden", None, [("top", 1, 2)])
    _glyph(font, "ringcomb.case", None, [("_top.case", 60.5, 700), ("top_1", 1, 1)], 0)
    font["A"].appendAnchor({"name": "top.case", "x": 255.5, "y": 900})
    font.lib["public.skipExportGlyphs"] = ["hidden"]
    return font


def defined_classes():
    """The file defines @mark_top with gravecomb where its anchor is and acutecomb
    elsewhere (a new class @mark_top_1), a class named as the filtering set ufo2ft
    would name, and has a mark feature (only mkmk is written)."""
    fea = LATIN_FEA + ("markClass [gravecomb] <anchor 100 500> @mark_top;\n"
                       "markClass [acutecomb] <anchor 1 2> @mark_top;\n"
                       "@MFS_mark2mark_top = [gravecomb];\n"
                       "feature mark {\n    pos base A <anchor 250 700> mark @mark_top;\n"
                       "} mark;\n")
    return latin(fea)


def kerned():
    """Anchors, kerning and no feature but languagesystems: ufo2ft's kern writer,
    then its mark writer, write into one file."""
    font = latin()
    font.kerning[("A", "O")] = -30
    font.kerning[("o", "space")] = 10
    return font


def hebrew():
    font = ufoLib2.Font()
    font.info.familyName = "Hebrew Mark Test"
    font.features.text = "languagesystem DFLT dflt;\nlanguagesystem hebr dflt;\n"
    _glyph(font, "bet-hb", 0x5D1, [("top", 300, 600), ("bottom", 310, 0)])
    _glyph(font, "shin-hb", 0x5E9, [("top", 320, 600), ("topright", 500, 600)])
    _glyph(font, "dagesh-hb", 0x5BC, [("_center", 50, 250)], 0)
    _glyph(font, "bet-hb.dg", None, [("center", 290, 260)])
    _glyph(font, "patah-hb", 0x5B7, [("_bottom", 60, 0), ("bottom", 60, -90)], 0)
    _glyph(font, "shindot-hb", 0x5C1, [("_topright", 20, 600)], 0)
    return font


CASES = {"latin": latin, "latin_no_fea": lambda: latin("", {}), "all_cases": all_cases,
         "defined_classes": defined_classes, "kerned": kerned, "hebrew": hebrew}


@pytest.mark.parametrize("name", sorted(CASES))
def test_mark_features_are_ufo2fts(saved, name):
    path = saved(CASES[name]())
    reason, text = written(path)
    assert reason is None
    assert text == ufo2fts(path)
    assert "feature mkmk" in text


@pytest.mark.parametrize("make,pieces", [
    (all_cases, ["markClass gravecomb <anchor 100 500> @mark_top;",
                 "markClass acutecomb <anchor 120 500> @mark_top;",
                 "markClass ringcomb.case <anchor 61 700> @mark_top.case;",
                 "lookup mark2base {", "lookup mark2base_1 {", "lookup mark2base_2 {",
                 "pos base A\n            <anchor 260 710> mark @mark_top;",
                 "lookup mark2liga {", "lookup mark2liga_1 {", "ligComponent\n",
                 "<anchor NULL>\n            ligComponent\n                <anchor 600 700>",
                 "lookup mark2mark_top {", "@MFS_mark2mark_top = [acutecomb gravecomb];",
                 "lookupflag UseMarkFilteringSet @MFS_mark2mark_top;",
                 "pos mark acutecomb\n            <anchor 120 791> mark @mark_top;"]),
    (defined_classes, ["markClass acutecomb <anchor 120 500> @mark_top_1;",
                       "@MFS_mark2mark_top_1 = [acutecomb gravecomb];"]),
    (kerned, ["feature kern {", "feature mark {", "feature mkmk {"])])
def test_the_features_have_what_they_should(saved, make, pieces):
    """The comparison above is of features that hold the cases: mark classes and
    their definitions, a lookup per mark class, the repeated anchor's last
    place, ligature components (one without anchors), mark filtering sets, a
    file's mark class at another anchor renamed, a class name taken renamed,
    coordinates rounded as ufo2ft rounds them, the glyph not exported and the
    unpaired, ignored and numbered mark anchors left out."""
    _, text = written(saved(make()))
    for piece in pieces:
        assert piece in text, (piece, text)
    for absent in ("hidden", "center", "#note", "<anchor 1 1>"):
        assert absent not in text[text.index("feature mark"):], absent


@pytest.mark.parametrize("what", ["base", "mark"])
def test_a_moved_anchor_is_seen(saved, what):
    """The comparison fails when one anchor moves by one unit (a base's, a
    mark's)."""
    font = latin()
    path = saved(font, "a")
    glyph = font["o"] if what == "base" else font["acutecomb"]
    glyph.anchors[0].x += 1
    other = saved(font, "b")
    assert written(path)[1] != ufo2fts(other)


def _gdef(font):
    font.features.text += "table GDEF {\n    GlyphClassDef [A], , [gravecomb], ;\n} GDEF;\n"


def _contextual(font):
    font["A"].appendAnchor({"name": "*top", "x": 1, "y": 2})


def _indic(font):   # (the last case: combining marks and no languagesystem name
    # their scripts: Devanagari among them)
    _glyph(font, "ka-deva", 0x915, [("top", 200, 700)])
    font.features.text = ""


def _refused(font):
    font["gravecomb"].appendAnchor({"name": "_top_1", "x": 1, "y": 2})


@pytest.mark.parametrize("change,reason", [
    (_gdef, "GDEF"), (_contextual, "contextual"), (_indic, "abvm"), (_refused, "refuses"),
    (lambda font: setattr(font.features, "text", ""), "abvm")])
def test_what_the_port_does_not_cover_goes_to_ufo2ft(saved, change, reason):
    font = latin()
    change(font)
    got, _ = written(saved(font))
    assert got is not None and reason in got, got


@pytest.mark.parametrize("name", ["all_cases", "kerned", "hebrew"])
def test_tables_equal_ufo2fts(saved, tmp_path, monkeypatch, name):
    """The fonts stroked and compiled by morph (the mark and mkmk features written
    by mark_static; ufo2ft not called) and by ufo2ft (the source read by
    ufoLib2): every table byte for byte (GPOS, GDEF), CFF as decompiled."""
    from morph.fonts import stream
    from tests.fonts.test_tables_static import _both_ways, _same_tables

    calls, real = [], stream.compile_stored
    monkeypatch.setattr(stream, "compile_stored",
                        lambda font, *a, **k: calls.append(font) or real(font, *a, **k))
    (_, light), (_, heavy) = _both_ways(saved(CASES[name]()), tmp_path, ".otf")
    assert len(calls) == 1   # the ufoLib2 run's
    font = _same_tables(light, heavy)
    kinds = {lk.LookupType for lk in font["GPOS"].table.LookupList.Lookup}
    assert {4, 6} <= kinds and "GDEF" in font

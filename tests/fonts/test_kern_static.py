"""The kern feature written without ufo2ft (morph.fonts.kern_static) against ufo2ft's
KernFeatureWriter: the whole feature file ufo2ft's feature compiler builds from
(its writers' output, recorded in a ufo2ft compile of the source read by ufoLib2)
equals the tree morph writes, written out, character for character; so feaLib
builds the same GPOS from both.  Sources cover: Latin, Greek and Cyrillic glyphs
with common ones (digits, punctuation) kerned across scripts; class to class,
class to glyph and glyph to glyph pairs (exceptions over their classes); zero
class pairs (dropped); fractional values; pairs and group members naming glyphs
the font lacks or does not export; alternates reached through GSUB (they take
their base's script); languagesystems with languages; a class name the feature
file already uses.  Fonts outside what the port covers (right-to-left scripts,
a 'dist' script, a GDEF table) are shown to be left to ufo2ft.
"""

import pytest
import ufoLib2

from tests.fonts.feature_text import ufo2fts, written

LATIN = {"A": 0x41, "V": 0x56, "T": 0x54, "o": 0x6F, "e": 0x65, "a": 0x61, "period": 0x2E,
         "comma": 0x2C, "one": 0x31, "seven": 0x37, "hyphen": 0x2D, "space": 0x20}
GREEK = {"Alpha": 0x391, "Tau": 0x3A4, "omicron": 0x3BF}
CYRILLIC = {"A-cy": 0x410, "Te-cy": 0x422, "o-cy": 0x43E}


def _font(codes, groups, kerning, fea="", skip=(), extra=()):
    font = ufoLib2.Font()
    font.info.familyName = "Kern Test"
    for name, code in codes.items():
        g = font.newGlyph(name)
        g.width = 500
        g.unicodes = [code]
    for name in extra:
        font.newGlyph(name).width = 500
    font.groups.update(groups)
    font.kerning.update(kerning)
    font.features.text = fea
    if skip:
        font.lib["public.skipExportGlyphs"] = list(skip)
    return font


def many_scripts():
    codes = dict(LATIN, **GREEK, **CYRILLIC)
    groups = {"public.kern1.A": ["A", "Alpha", "A-cy"], "public.kern2.A": ["A", "Alpha", "A-cy"],
              "public.kern1.T": ["T", "Tau", "Te-cy", "missing"],
              "public.kern2.o": ["o", "omicron", "o-cy", "e", "o.alt"],
              "public.kern2.period": ["period", "comma"], "public.kern1.one": ["one", "seven"],
              "public.kern1.empty": ["missing2"], "public.kern2.hidden": ["hidden"]}
    kerning = {("public.kern1.A", "V"): -60, ("public.kern1.T", "public.kern2.o"): -80.4,
               ("T", "e"): -40, ("Tau", "omicron"): 0,
               ("public.kern1.T", "public.kern2.period"): -70,
               ("public.kern1.one", "public.kern2.period"): -30, ("A", "hyphen"): -10,
               ("public.kern1.A", "public.kern2.A"): 0, ("V", "public.kern2.A"): -55.5,
               ("missing", "A"): -5, ("public.kern1.nothere", "A"): -5,
               ("space", "public.kern2.A"): -15, ("public.kern1.empty", "V"): -20,
               ("T", "public.kern2.hidden"): -25, ("A-cy", "Te-cy"): -35}
    fea = ("languagesystem DFLT dflt;\nlanguagesystem latn dflt;\nlanguagesystem latn TRK;\n"
           "languagesystem grek dflt;\n@kern1.Latn.A = [A];\n"
           "feature salt {\n    sub o by o.alt;\n} salt;\n")
    return _font(codes, groups, kerning, fea, skip=["hidden"], extra=["o.alt", "hidden"])


def latin_no_fea():
    groups = {"public.kern1.A": ["A"], "public.kern2.V": ["V", "T"]}
    kerning = {("public.kern1.A", "public.kern2.V"): -50, ("A", "T"): -20, ("one", "seven"): 5}
    return _font(LATIN, groups, kerning)


def common_only():
    codes = {"one": 0x31, "seven": 0x37, "period": 0x2E}
    return _font(codes, {}, {("seven", "period"): -40, ("one", "one"): 10})


@pytest.mark.parametrize("make", ["many_scripts", "separate_scripts", "latin_no_fea",
                                  "common_only"])
def test_kern_feature_is_ufo2fts(saved, make):
    path = saved(globals()[make]())
    reason, text = written(path)
    assert reason is None
    assert text == ufo2fts(path)
    assert "feature kern" in text


def separate_scripts():
    """Latin, Greek and Cyrillic kerned apart (a lookup each), a class name the
    feature file already has."""
    codes = dict(LATIN, **GREEK, **CYRILLIC)
    groups = {"public.kern1.A": ["A"], "public.kern2.o": ["o", "e", "o.alt"],
              "public.kern1.Tau": ["Tau"], "public.kern2.omicron": ["omicron"],
              "public.kern1.Te": ["Te-cy"], "public.kern2.o-cy": ["o-cy"]}
    kerning = {("public.kern1.A", "public.kern2.o"): -20, ("A", "o"): -25,
               ("public.kern1.Tau", "public.kern2.omicron"): -30,
               ("public.kern1.Te", "public.kern2.o-cy"): -35, ("seven", "period"): -40}
    fea = ("languagesystem DFLT dflt;\nlanguagesystem latn dflt;\n"
           "@kern1.Latn.A = [A];\nfeature salt {\n    sub e by o.alt;\n} salt;\n")
    return _font(codes, groups, kerning, fea, extra=["o.alt"])


@pytest.mark.parametrize("make,pieces", [
    (many_scripts, ["lookup kern_Cyrl_Grek_Latn", "lookup kern_Default", "language TRK;",
                    "@kern2.Cyrl_Grek_Latn.o = [e o o-cy o.alt omicron];", "pos T e -40;",
                    "@kern2.Cyrl_Grek_Latn.o -80;", "-55;", "script cyrl;"]),
    (separate_scripts, ["lookup kern_Latn", "lookup kern_Grek", "lookup kern_Cyrl",
                        "lookup kern_Default", "@kern1.Latn.A_1", "o.alt", "pos A o -25;"])])
def test_the_feature_has_what_it_should(saved, make, pieces):
    """The comparison above is of features that hold the cases: a lookup per
    script or one for scripts whose classes mix them, the common lookup, the
    alternate kerned in its base's class, exceptions before their class pairs,
    values rounded as ufo2ft rounds them, a class name taken in the file renamed,
    zero class pairs and glyphs the font lacks or does not export left out."""
    _, text = written(saved(make()))
    for piece in pieces:
        assert piece in text, piece
    kern = text[text.index("lookup kern_"):]
    assert "missing" not in kern and "hidden" not in kern and "nothere" not in kern


def test_a_changed_value_is_seen(saved):
    """The comparison fails when one kerning value differs by one unit."""
    font = many_scripts()
    path = saved(font, "a")
    font.kerning[("T", "e")] = -41
    other = saved(font, "b")
    assert written(path)[1] != ufo2fts(other)


@pytest.mark.parametrize("codes,fea,reason", [
    ({"alef-ar": 0x627, "beh-ar": 0x628}, "", "right-to-left"),
    ({"A": 0x41, "bet-hb": 0x5D1}, "", "right-to-left"),
    ({"ka-deva": 0x915, "kha-deva": 0x916}, "", "dist"),
    ({"A": 0x41, "V": 0x56}, "table GDEF {\n    GlyphClassDef [A], , [V], ;\n} GDEF;\n",
     "GDEF"),
])
def test_what_the_port_does_not_cover_goes_to_ufo2ft(saved, codes, fea, reason):
    names = list(codes)
    font = _font(codes, {}, {(names[0], names[1]): -20}, fea)
    got, _ = written(saved(font))
    assert got is not None and reason in got, got

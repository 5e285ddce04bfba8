"""Static fonts of sources with kerning, groups, anchors, components, production
names and glyphs not exported, compiled without ufo2ft (morph.fonts.tables_static,
its feature-writer check morph.fonts.writers_static, read by morph.parse.light_ufo)
against ufo2ft, as in test_tables_static.py: the source read light and read with
ufoLib2, each stroked with the same nib and tolerance; every table byte-identical
(GPOS and GDEF too), head but for its time stamps, CFF equal as decompiled.

Sources:

- Relief "featured": the Relief SingleLine subset (kerning pairs and exceptions
  between glyphs and classes, 40 groups, anchors, composites, glyphs not exported
  named in the lib) whose feature file is what ufo2ft's feature writers make of it
  (its kern, mark and mkmk features written out): ufo2ft's writers then add
  nothing, and morph builds every table itself (no ufo2ft, no ufoLib2 imported);
- the Relief subset as it is: its anchors have no mkmk feature, which morph
  writes as ufo2ft's mark writer does (morph.fonts.mark_static, compared with
  ufo2ft's in test_mark_static.py);
- the Relief subset without anchors: kerning and groups and no kern feature, which
  morph writes as ufo2ft's kern writer does (morph.fonts.kern_static, compared
  with ufo2ft's in test_kern_static.py);
- a Hershey-like source with composites (one of a glyph not exported), production
  names (one invalid, one repeated) and one kerning pair with a kern feature.

TrueType fonts keeping components are compiled by morph too
(morph.fonts.glyf_static: ufo2ft's component flags; more cases in
test_glyf_static.py), glyf and loca byte-identical to ufo2ft's.
"""

import subprocess
import sys
import textwrap

import pytest
import ufoLib2
from fontTools.ttLib import TTFont

from morph.fonts.writers_static import DIST_OR_ABVM_SCRIPTS, writers_add_nothing
from morph.parse.light_ufo import LightFont, LightInfo
from tests import RELIEF_SUBSET
from tests.fontfixtures import hershey_like, skeleton_line
from tests.fonts.test_tables_static import _both_ways, _same_tables


def ufo2ft_features(font):
    """The feature file ufo2ft's default writers make of ``font``'s."""
    from ufo2ft.featureCompiler import FeatureCompiler
    from ufo2ft.util import makeOfficialGlyphOrder

    tt = TTFont()
    tt.setGlyphOrder(makeOfficialGlyphOrder(font))
    compiler = FeatureCompiler(font, tt)
    compiler.setupFeatures()
    return compiler.features


def relief_featured():
    font = ufoLib2.Font.open(RELIEF_SUBSET, lazy=False)
    font.features.text = ufo2ft_features(font)
    assert "feature kern" in font.features.text and "feature mkmk" in font.features.text
    return font


def relief_as_is():
    return ufoLib2.Font.open(RELIEF_SUBSET, lazy=False)


def relief_kerned():
    """The Relief subset without its glyphs' anchors: kerning and groups with no
    kern feature in the file, which morph writes (morph.fonts.kern_static)."""
    font = relief_as_is()
    for g in font:
        g.anchors.clear()
    return font


def composites_like():
    """hershey_like with composites (Agrave: A and gravecomb moved; lcross: l and
    the unexported _bar; Aslant: a contour of its own and A turned and scaled;
    Agrave.ss: Agrave moved by a fraction of a unit, components of a component),
    production names (A -> "A.alt"; "l" -> "l!", invalid characters stripped;
    "O" -> "A.alt", repeated: ".1" added), a kerning pair and the kern feature
    that holds it."""
    font = hershey_like()
    font.newGlyph("Agrave").width = 567
    pen = font["Agrave"].getPointPen()
    pen.addComponent("A", (1, 0, 0, 1, 0, 0))
    pen.addComponent("gravecomb", (1, 0, 0, 1, 400, 120))
    font.newGlyph("_bar").width = 250
    skeleton_line(font["_bar"], (60, 350), (190, 350))
    font.newGlyph("lcross").width = 250
    font["lcross"].getPointPen().addComponent("l", (1, 0, 0, 1, 0, 0))
    font["lcross"].getPointPen().addComponent("_bar", (1, 0, 0, 1, 0, 0))
    font.newGlyph("Aslant").width = 600   # own contours, a turned and scaled A
    skeleton_line(font["Aslant"], (40, 20), (560, 20))
    font["Aslant"].getPointPen().addComponent("A", (0.83, 0.11, -0.17, 0.79, 33.3, 17.5))
    font.newGlyph("Agrave.ss").width = 580   # nested: Agrave's components moved again
    font["Agrave.ss"].getPointPen().addComponent("Agrave", (1, 0, 0, 1, 10.5, -3.25))
    font.lib["public.skipExportGlyphs"] = ["_bar"]
    font.lib["public.postscriptNames"] = {"A": "A.alt", "l": "l!", "O": "A.alt"}
    font.kerning[("A", "O")] = -20
    font.features.text = "feature kern {\n    pos A O -20;\n} kern;\n"
    return font


SOURCES = {"featured": relief_featured, "as_is": relief_as_is, "kerned": relief_kerned,
           "composites": composites_like}


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    folder = tmp_path_factory.mktemp("features")
    paths = {}
    for name, make in SOURCES.items():
        paths[name] = folder / ("%s.ufo" % name)
        make().save(paths[name])
    return paths


@pytest.mark.parametrize("name,kind,by_ufo2ft", [
    ("featured", ".otf", False), ("featured", ".ttf", False),
    ("as_is", ".otf", False), ("kerned", ".otf", False), ("composites", ".otf", False),
    ("composites", ".ttf", False)])
def test_tables_equal_ufo2fts(saved, tmp_path, ufo2ft_calls, name, kind, by_ufo2ft):
    """The light font compiled by morph (or, ``by_ufo2ft``, left to ufo2ft) gives
    ufo2ft's font of the source read by ufoLib2."""
    (light, a), (heavy, b) = _both_ways(saved[name], tmp_path, kind)
    assert isinstance(light, LightFont) and not isinstance(heavy, LightFont)
    # the light run's compile, then the ufoLib2 run's
    assert ufo2ft_calls == (["Font", "Font"] if by_ufo2ft else ["Font"])
    font = _same_tables(a, b)
    if name != "composites":
        assert {"GPOS", "GDEF", "GSUB"} <= set(font.keys())
    order = font.getGlyphOrder()
    if name == "composites":
        assert "_bar" not in order and "lcross" in order
        if kind == ".otf":
            assert {"A.alt", "l", "A.alt.1"} <= set(order)


def test_compiled_without_ufo2ft_or_ufolib2(saved, tmp_path):
    """The featured Relief subset (kerning, groups, anchors, composites) is stroked
    and compiled to .otf in a process that never imports ufo2ft or ufoLib2."""
    code = textwrap.dedent("""
        import sys
        from morph.fonts.brush import ellipse_nib
        from morph.fonts.stream import SkeletonSource
        from morph.fonts.stroke import stroke_ufo
        stats = stroke_ufo(SkeletonSource(sys.argv[1], light=True), sys.argv[2],
                           ellipse_nib(90.0, 20.0, 30.0), None, tol=0.5)
        assert stats["composites"] > 0, stats
        print(sorted(m for m in ("ufo2ft", "ufoLib2") if m in sys.modules))
    """)
    out = subprocess.run([sys.executable, "-c", code, str(saved["featured"]),
                          str(tmp_path / "f.otf")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


def _first_pair_value(font):
    for lookup in font["GPOS"].table.LookupList.Lookup:
        for st in lookup.SubTable:
            st = getattr(st, "ExtSubTable", st)
            if st.Format == 1 and getattr(st, "PairSet", None):
                return st.PairSet[0].PairValueRecord[0].Value1
            if st.Format == 2 and getattr(st, "Class1Record", None):
                for rec in st.Class1Record:
                    for rec2 in rec.Class2Record:
                        if rec2.Value1 is not None and getattr(rec2.Value1, "XAdvance", 0):
                            return rec2.Value1
    raise AssertionError("no kerning")


def _first_base_anchor(font):
    for lookup in font["GPOS"].table.LookupList.Lookup:
        if lookup.LookupType == 4:
            return lookup.SubTable[0].BaseArray.BaseRecord[0].BaseAnchor[0]
    raise AssertionError("no mark to base")


def _first_mark2_anchor(font):
    for lookup in font["GPOS"].table.LookupList.Lookup:
        if lookup.LookupType == 6:
            return lookup.SubTable[0].Mark2Array.Mark2Record[0].Mark2Anchor[0]
    raise AssertionError("no mark to mark")


@pytest.mark.parametrize("what,name", [("kerning", "featured"), ("anchor", "featured"),
                                       ("mkmk anchor", "as_is")])
def test_a_changed_kern_value_or_anchor_is_seen(saved, tmp_path, what, name):
    """The comparison fails when one kerning value, one base anchor or one mark
    to mark anchor (of the mkmk feature morph writes) of the light font's GPOS is
    moved by one unit."""
    (_, a), (_, b) = _both_ways(saved[name], tmp_path, ".otf")
    font = TTFont(str(a))
    if what == "kerning":
        _first_pair_value(font).XAdvance += 1
    elif what == "anchor":
        _first_base_anchor(font).XCoordinate += 1
    else:
        _first_mark2_anchor(font).YCoordinate += 1
    font.save(str(tmp_path / "changed.otf"))
    _same_tables(a, b)
    with pytest.raises(AssertionError, match="GPOS"):
        _same_tables(tmp_path / "changed.otf", b)


def test_shells_read_light_hold_ufolib2s(saved):
    """The light reader's shells of the Relief subset hold ufoLib2's anchors,
    components, groups and kerning."""
    from morph.fonts.stream import SkeletonSource

    for name in ("as_is", "composites"):
        a = SkeletonSource(saved[name], light=True).shell_font()
        b = SkeletonSource(saved[name]).shell_font()
        assert isinstance(a, LightFont)
        assert a.kerning == dict(b.kerning) and a.groups == {k: list(v) for k, v in
                                                             b.groups.items()}
        for g in b:
            ga = a[g.name]
            assert [(c.baseGlyph, tuple(c.transformation), c.identifier)
                    for c in ga.components] == \
                [(c.baseGlyph, tuple(c.transformation), c.identifier) for c in g.components]
            assert [(p.name, p.x, p.y, p.identifier) for p in ga.anchors] == \
                [(p.name, p.x, p.y, p.identifier) for p in g.anchors]


class _Glyph:
    def __init__(self, anchors=(), unicodes=()):
        self.anchors = [type("A", (), {"name": n}) for n in anchors]
        self.unicodes = list(unicodes)


def _font(text, kerning=None, glyphs=()):
    font = LightFont(None, LightInfo(), {}, type("F", (), {"text": text})(), {},
                     kerning=kerning)
    return font, list(glyphs)


@pytest.mark.parametrize("text,kerning,anchors,codes,reason", [
    ("", {("A", "V"): -10}, (), (0x41,), "kerning without a kern feature"),
    ("feature kern { pos A V -10; } kern;", {("A", "V"): -10}, (), (0x41,), None),
    ("languagesystem DFLT dflt; languagesystem dev2 dflt;\n"
     "feature kern { pos A V -10; } kern;", {("A", "V"): -10}, (), (0x41,),
     "kerning in a script of the dist feature"),
    ("feature kern { pos A V -10; } kern;", {("A", "V"): -10}, (), (0x915,),
     "kerning in a script of the dist feature"),
    ("feature mark { } mark;", None, ("top",), (0x41,), "anchors without mark and mkmk"),
    ("feature mark { } mark; feature mkmk { } mkmk;", None, ("top",), (0x41,), None),
    ("feature mark { } mark; feature mkmk { } mkmk;", None, ("top",), (0x300,),
     "anchors in a script of the abvm / blwm features"),
    ("languagesystem latn dflt;\nfeature mark { } mark; feature mkmk { } mkmk;", None,
     ("top",), (0x300,), None),
    ("", None, ("entry",), (0x41,), "cursive anchors"),
    ("", None, ("caret_1",), (0x41,), "ligature caret"),
    ("feature kern {\n# Automatic Code\n} kern;", {("A", "V"): -10}, (), (0x41,),
     "insertion marker"),
])
def test_writers_add_nothing_reasons(text, kerning, anchors, codes, reason):
    """Each input ufo2ft's writers would write from leaves the font to ufo2ft; the
    same font with the feature ufo2ft would write already there does not."""
    from io import StringIO

    from fontTools.feaLib.parser import Parser

    tree = Parser(StringIO(text), {"A", "V"}).parse() if text else None
    font, glyphs = _font(text, kerning, [_Glyph(anchors, codes)])
    got = writers_add_nothing(font, tree, glyphs, set(codes))
    assert (got is None) if reason is None else (reason in got), got


def test_scripts_are_ufo2fts():
    from ufo2ft.constants import INDIC_SCRIPTS, USE_SCRIPTS

    assert DIST_OR_ABVM_SCRIPTS == set(INDIC_SCRIPTS) | set(USE_SCRIPTS) | {"Khmr", "Mymr"}


@pytest.mark.parametrize("text,codes,reason", [
    ("", (0x41,), None),
    ("languagesystem latn dflt;\n", (0x300,), None),
    ("", (0x300,), "anchors in a script of the abvm / blwm features"),
    ("", (0x915,), "anchors in a script of the abvm / blwm features")])
def test_anchors_with_the_mark_features_written(text, codes, reason):
    """Anchors without mark and mkmk features in the file are no reason where
    morph writes those features (``mark_written``); an abvm / blwm script still
    is."""
    from io import StringIO

    from fontTools.feaLib.parser import Parser

    tree = Parser(StringIO(text), {"A"}).parse() if text else None
    font, glyphs = _font(text, None, [_Glyph(("top",), codes)])
    got = writers_add_nothing(font, tree, glyphs, set(codes), mark_written=True)
    assert (got is None) if reason is None else (reason in got), got


def test_composites_drawn_where_their_bases_are_not_read(saved, tmp_path, monkeypatch):
    """A composite whose stored bases the charstring reader does not take is
    decomposed with fontTools' pens: the same font as ufo2ft's."""
    import morph.parse.charstrings as charstrings

    monkeypatch.setattr(charstrings, "charstring_outlines", lambda items: [None] * len(items))
    (_, a), (_, b) = _both_ways(saved["composites"], tmp_path, ".otf")
    _same_tables(a, b)

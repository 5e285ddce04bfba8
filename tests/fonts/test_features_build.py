"""The layout tables of morph.fonts.tables_static without their round trips:

- the kern writer's GSUB closure (morph.fonts.kern_static._close) against
  fontTools.subset's, on the repo's feature file and synthetic ones of every
  substitution kind the direct closure reads (single, multiple, alternate,
  ligature, extension lookups, lookups no feature references) and a contextual
  one it leaves to the subsetter;
- the tables built from the feature tree against the tree written out and parsed
  again with the font's glyph order (ufo2ft's way), and the fonts whose parse with
  that glyph order would differ (a glyph not exported named in the text, a
  hyphenated name) built the round-trip way;
- feaLib imported without running fontTools.varLib's package, which runs whole at
  its first use.
"""

import subprocess
import sys
import textwrap
from io import StringIO

import pytest
from fontTools.feaLib.builder import addOpenTypeFeatures
from fontTools.feaLib.parser import Parser
from fontTools.ttLib import TTFont

from morph.fonts import tables_static as T
from morph.fonts.kern_static import _close, _substitutions
from morph.fonts.stream import SkeletonSource
from tests import RELIEF_SUBSET

GLYPHS = ["a", "b", "c", "d", "e", "f", "f_i", "f_f_i", "i", "a.alt", "a.sc", "b.sc",
          "c.sc", "d.alt", "d.alt2", "x", "y"]

SYNTHETIC = {
    "single": "feature smcp { sub [a b c] by [a.sc b.sc c.sc]; } smcp;",
    "chained single": "feature salt { sub a by a.alt; } salt;\n"
                      "feature ss01 { sub a.alt by d; sub d by d.alt; } ss01;",
    "multiple": "feature ccmp { sub f_i by f i; sub d.alt2 by x y; } ccmp;",
    "alternate": "feature aalt { sub d from [d.alt d.alt2]; } aalt;",
    # f_f_i comes in only once f_i is there (components of ligatures made of ligatures)
    "ligatures": "feature liga { sub f i by f_i; sub f f_i by f_f_i; sub x y by e; } liga;",
    "extension": "lookup EXT useExtension { sub a by a.alt; } EXT;\n"
                 "feature salt { lookup EXT; } salt;",
    "unreferenced": "lookup NONE { sub a by x; } NONE;\nfeature salt { sub b by y; } salt;",
    "scripts": "languagesystem DFLT dflt; languagesystem latn dflt; languagesystem latn TRK;\n"
               "feature locl { script latn; language TRK; sub i by x; } locl;",
}

CONTEXTUAL = "feature calt { sub a' b by a.alt; } calt;"


def _gsub(text, order=GLYPHS):
    tt = TTFont()
    tt.setGlyphOrder([".notdef"] + list(order))
    addOpenTypeFeatures(tt, Parser(StringIO(text), set(order)).parse(), tables={"GSUB"})
    return tt["GSUB"]


def _subsetters(gsub, glyphs):
    from fontTools import subset

    s = subset.Subsetter()
    s.glyphs = set(glyphs)
    gsub.closure_glyphs(s)
    return s.glyphs


STARTS = [{"a"}, {"f", "i"}, {"f"}, {"d"}, {"x", "y"}, {"a", "b", "c", "d", "f", "i", "x", "y"},
          {"b", "d.alt2"}]


@pytest.mark.parametrize("name", sorted(SYNTHETIC))
def test_closure_is_the_subsetters(name):
    gsub = _gsub(SYNTHETIC[name])
    assert _substitutions(gsub.table) is not None     # read here, not by the subsetter
    for start in STARTS:
        mine = set(start)
        _close(gsub, mine)
        assert mine == _subsetters(gsub, start), (name, start)


def test_closure_grows_where_it_should():
    """The cases above are not all trivial: the closure adds glyphs through chains."""
    grown = {}
    for name in ("chained single", "ligatures", "multiple"):
        glyphs = {"a", "f", "i", "d.alt2"}
        _close(_gsub(SYNTHETIC[name]), glyphs)
        grown[name] = glyphs - {"a", "f", "i", "d.alt2"}
    assert grown == {"chained single": {"a.alt", "d", "d.alt"}, "ligatures": {"f_i", "f_f_i"},
                     "multiple": {"x", "y"}}


def test_contextual_closure_left_to_the_subsetter():
    gsub = _gsub(CONTEXTUAL)
    assert _substitutions(gsub.table) is None
    for start in ({"a"}, {"a", "b"}):
        mine = set(start)
        _close(gsub, mine)
        assert mine == _subsetters(gsub, start)
    assert "a.alt" in _subsetters(gsub, {"a", "b"})


def test_closure_of_the_repos_feature_file():
    light = SkeletonSource(RELIEF_SUBSET, light=True).shell_font()
    gsub = _gsub(light.features.text, sorted(light.keys()))
    assert _substitutions(gsub.table)[0]              # g -> g.ss01
    for start in ({"g"}, {"a", "g", "n"}, set(light.keys()) - {"g.ss01"}):
        mine = set(start)
        _close(gsub, mine)
        assert mine == _subsetters(gsub, start)
        assert ("g.ss01" in mine) == ("g" in start)


# ------------------------------------------------------------------ tree vs round trip

def _layout(compiler, tree, round_trip):
    """The GSUB, GPOS and GDEF bytes of ``tree`` built on ``compiler``'s glyph order,
    from the tree or written out and parsed again."""
    tt = TTFont()
    tt.setGlyphOrder(compiler.order)
    if round_trip:
        from fontTools.feaLib.builder import addOpenTypeFeaturesFromString

        addOpenTypeFeaturesFromString(tt, tree.asFea())
    else:
        addOpenTypeFeatures(tt, tree)
    return {tag: tt[tag].compile(tt) for tag in ("GSUB", "GPOS", "GDEF") if tag in tt}


def test_tree_built_as_written_out_and_parsed():
    """The Relief subset (glyphs not exported, none named in its text) with its kern
    and mkmk features written by morph's writers: built from the tree, its tables
    are the round trip's."""
    light = SkeletonSource(RELIEF_SUBSET, light=True).shell_font()
    compiler = T._Compiler(light, {}, True)
    assert compiler._same_parse() and set(light.keys()) - set(compiler.order)
    tree = T.parse_features(light)
    reason, writers = T.left_to_ufo2ft(light, ".otf", tree, compiler.order, compiler.cmap)
    assert reason is None and len(writers) == 2
    assert all(w.write() for w in writers)
    direct = _layout(compiler, tree, False)
    assert sorted(direct) == ["GDEF", "GPOS", "GSUB"]
    assert direct == _layout(compiler, tree, True)


def _light(tmp_path, glyphs, skipped, text):
    """The light font and compiler of a UFO of empty glyphs ``glyphs`` (those in
    ``skipped`` not exported) with the feature file ``text``."""
    import ufoLib2

    font = ufoLib2.Font()
    for name in glyphs:
        font.newGlyph(name).width = 100
    font.lib["public.skipExportGlyphs"] = skipped
    font.features.text = text
    font.save(tmp_path / "f.ufo")
    light = SkeletonSource(tmp_path / "f.ufo", light=True).shell_font()
    return light, T._Compiler(light, {}, True)


@pytest.mark.parametrize("text, same", [
    ("feature salt { sub a by b; } salt;", True),
    ("feature salt { sub a by c-d; } salt;", False),   # the glyph not exported
    ("feature salt { sub c-d by b; } salt;", False),
    ("feature salt { sub [a - b] by c; } salt;", True),
    ("feature salt { sub a by .notdef; } salt;", False),
    ('include(other.fea);', False),
])
def test_parse_differs_only_where_a_name_of_one_glyph_set_is_in_the_text(tmp_path, text, same):
    light, compiler = _light(tmp_path, ["a", "b", "c", "d", "c-d"], ["c-d"], text)
    assert compiler._same_parse() is same


def test_hyphenated_name_parses_apart_by_glyph_set():
    """Why a name of one glyph set only sends the file the round-trip way: ``c-d``
    is a glyph of the UFO, and a range (in a class) or an error (alone) with the
    exported glyphs."""
    from fontTools.feaLib.error import FeatureLibError

    ufo, exported = {"a", "b", "c", "d", "c-d"}, {".notdef", "a", "b", "c", "d"}
    text = "feature salt { sub [c-d] by b; } salt;"
    assert "[c-d]" in Parser(StringIO(text), ufo).parse().asFea()
    assert "[c - d]" in Parser(StringIO(text), exported).parse().asFea()
    text = "feature salt { sub c-d by b; } salt;"
    assert "sub c-d by b" in Parser(StringIO(text), ufo).parse().asFea()
    with pytest.raises(FeatureLibError, match="missing"):
        Parser(StringIO(text), exported).parse()


# ------------------------------------------------------------------ imports

_PROBE = textwrap.dedent("""
    import sys
    from morph.fonts.deferred import feature_builder, feature_parser
    feature_parser(); feature_builder()
    print("merger" if "fontTools.varLib.merger" in sys.modules else "no merger")
    import fontTools.varLib
    print(callable(fontTools.varLib.build), "fontTools.varLib.merger" in sys.modules)
""")


def test_fealib_without_the_variation_package():
    """feaLib's parser and builder import without fontTools.varLib's ``__init__``
    (its merger); the package runs whole at the first use of its own names."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    res = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                         cwd=root, env={"PYTHONPATH": str(root), "PATH": "/usr/bin:/bin"},
                         timeout=120)
    assert res.returncode == 0, res.stderr
    assert res.stdout.split("\n")[:2] == ["no merger", "True True"]

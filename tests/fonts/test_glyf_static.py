"""TrueType fonts keeping components, compiled without ufo2ft
(morph.fonts.glyf_static through morph.fonts.tables_static) against ufo2ft, as in
test_tables_static.py: the source read light and read with ufoLib2, each stroked
with the same nib and tolerance into .ttf; every table byte-identical (glyf,
loca, hmtx, maxp too), head but for its time stamps.

The source (hershey_like with composites) covers: a composite of a base and a
mark moved (USE_MY_METRICS set by ufo2ft's rule: the base of the composite's
advance, not moved horizontally), a composite whose only component is moved
horizontally (no flag), one moved vertically (flagged), a scaled and a flipped
component (the 2x2 matrix, one value just under +2 clamped), a composite of a
composite (depth 2 in maxp), a glyph with its own contours and a component
(decomposed), object libs that clear ROUND_XY_TO_GRID and set USE_MY_METRICS on
a second component, anchors on the glyphs (mark features written by
mark_static).  A matrix beyond F2Dot14 or a component of a glyph not exported
leaves the font to ufo2ft, with the same result.
"""

import pytest
from fontTools.ttLib import TTFont

from tests.fontfixtures import hershey_like, skeleton_line
from tests.fonts.test_tables_static import _both_ways, _same_tables

#: glyph -> its components: (base, transformation, identifier)
COMPOSITES = {
    "Agrave": [("A", (1, 0, 0, 1, 0, 0), None), ("gravecomb", (1, 0, 0, 1, 400, 120), None)],
    "Ashift": [("A", (1, 0, 0, 1, 30, 0), None)],
    "Araised": [("A", (1, 0, 0, 1, 0, 40.4), None)],
    "Oturned": [("O", (-1, 0, 0, -1, 600, 700), None)],
    "Agravedot": [("Agrave", (1, 0, 0, 1, 0, 0), None), ("period", (1, 0, 0, 1, 250, 0), None)],
    "Ilib": [("l", (1, 0, 0, 1, 0.4, 0), "c1"), ("l", (1, 0, 0, 1, 100, 0), "c2")],
}


def composites_font(change=None):
    font = hershey_like()
    for name, comps in COMPOSITES.items():
        g = font.newGlyph(name)
        g.width = font[comps[0][0]].width
        pen = g.getPointPen()
        for base, matrix, ident in comps:
            pen.addComponent(base, matrix, identifier=ident)
    font["Ilib"].lib["public.objectLibs"] = {
        "c1": {"public.truetype.roundOffsetToGrid": False},
        "c2": {"public.truetype.useMyMetrics": True}}
    mixed = font.newGlyph("Obar")
    mixed.width = 600
    skeleton_line(mixed, (50, -250), (550, -250))
    mixed.getPointPen().addComponent("O", (1, 0, 0, 1, 0, 0))
    font["A"].appendAnchor({"name": "top", "x": 378, "y": 700})
    font["gravecomb"].appendAnchor({"name": "_top", "x": -110, "y": 600})
    font.features.text = "languagesystem DFLT dflt;\nlanguagesystem latn dflt;\n"
    if change is not None:
        change(font)
    return font


def _not_exported(font):
    font.lib["public.skipExportGlyphs"] = ["period"]


@pytest.mark.parametrize("change,by_ufo2ft", [(None, False), (_not_exported, True)])
def test_composites_equal_ufo2fts(tmp_path, ufo2ft_calls, change, by_ufo2ft):
    path = tmp_path / "c.ufo"
    composites_font(change).save(path)
    (_, a), (_, b) = _both_ways(path, tmp_path, ".ttf")
    assert ufo2ft_calls == (["Font", "Font"] if by_ufo2ft else ["Font"])
    font = _same_tables(a, b)
    if change is None:
        _has_the_cases(font)


def _has_the_cases(font):
    """The compared font holds the cases the module docstring names."""
    from fontTools.ttLib.tables._g_l_y_f import ROUND_XY_TO_GRID, USE_MY_METRICS

    glyf = font["glyf"]

    def flags(name):
        return [c.flags for c in glyf[name].components]

    assert flags("Agrave") == [ROUND_XY_TO_GRID | USE_MY_METRICS, ROUND_XY_TO_GRID]
    assert flags("Ashift") == [ROUND_XY_TO_GRID]
    assert flags("Araised") == [ROUND_XY_TO_GRID | USE_MY_METRICS]
    assert glyf["Araised"].components[0].y == 40
    assert flags("Ilib") == [0, ROUND_XY_TO_GRID | USE_MY_METRICS]
    assert glyf["Oturned"].components[0].transform[0][0] == -1
    assert glyf["Agravedot"].isComposite() and font["maxp"].maxComponentDepth == 2
    assert not glyf["Obar"].isComposite() and glyf["Obar"].numberOfContours > 1
    assert "GPOS" in font


def test_a_changed_component_is_seen(tmp_path):
    """The comparison fails when one component offset moves by one unit, or one
    component flag changes."""
    path = tmp_path / "c.ufo"
    composites_font().save(path)
    (_, a), (_, b) = _both_ways(path, tmp_path, ".ttf")
    for change in ("offset", "flag"):
        font = TTFont(str(a))
        comp = font["glyf"]["Agrave"].components[1]
        if change == "offset":
            comp.x += 1
        else:
            comp.flags ^= 0x200   # USE_MY_METRICS
        font.save(str(tmp_path / "changed.ttf"))
        with pytest.raises(AssertionError, match="glyf"):
            _same_tables(tmp_path / "changed.ttf", b)


def test_what_is_not_written_here_is_named():
    """A component matrix beyond F2Dot14 (ufo2ft decomposes the glyph) and a
    component of a glyph not exported or missing are reasons for ufo2ft; a
    matrix value just under +2 (clamped) is not."""
    from morph.fonts.glyf_static import composite_reason
    from morph.parse.light_ufo import LightComponent, LightGlyph

    def font(matrix, base="O"):
        return {"O": LightGlyph("O"),
                "C": LightGlyph("C", components=[LightComponent(base, matrix)])}

    assert composite_reason(font((1, 0, 0, 1, 5, 5))) is None
    assert composite_reason(font((1.99995, 0, 0, -2, 5, 5))) is None
    assert "F2Dot14" in composite_reason(font((2.5, 0, 0, 1, 0, 0)))
    assert "not exported" in composite_reason(font((1, 0, 0, 1, 0, 0), base="X"))

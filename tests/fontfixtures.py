"""Test fonts built from the bundled Noto Sans with fontTools (no download).

- :func:`build_mark_font`: Noto Sans with combining marks positioned by GPOS
  (acutecomb, gravecomb; mark-to-base on e and o, mark-to-mark on acutecomb), the
  precomposed é/ó dropped from the cmap so that shaping e + U+0301 uses GPOS.
- :func:`build_variable_font`: a two-master variable font (axis wght 400-700):
  the default master is Noto Sans, the wght=700 master the same outlines scaled
  1.25x horizontally (advances too), built with designspaceLib + varLib.
- :func:`hershey_like`: a small skeleton UFO (ufoLib2) of single-stroke glyphs with
  nothing that needs ufo2ft's feature writers.
"""

import numpy as np
from fontTools.pens.boundsPen import BoundsPen
from fontTools.pens.transformPen import TransformPen
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib import TTFont

from morph.parse import default_font_path

WIDE = 1.25  # x scale of the wght=700 master


def bounds(font, name):
    pen = BoundsPen(font.getGlyphSet())
    font.getGlyphSet()[name].draw(pen)
    return pen.bounds


def finish_tables(fb, names, family, width, ascent, descent):
    """The tables every small test font built with FontBuilder needs after its
    outlines: hmtx (``width`` for every glyph of ``names``, lsb 0), hhea, name,
    OS/2 and post."""
    fb.setupHorizontalMetrics({n: (width, 0) for n in names})
    fb.setupHorizontalHeader(ascent=ascent, descent=descent)
    fb.setupNameTable({"familyName": family, "styleName": "Regular"})
    fb.setupOS2()
    fb.setupPost()


def _add_mark(font, name, source, code):
    """A zero-width combining mark: ``source``'s outline centred on x = 0."""
    gs = font.getGlyphSet()
    x0, _, x1, _ = bounds(font, source)
    pen = TTGlyphPen(gs)
    gs[source].draw(TransformPen(pen, (1, 0, 0, 1, -(x0 + x1) / 2.0, 0)))
    g = pen.glyph()
    font["glyf"][name] = g
    g.recalcBounds(font["glyf"])
    font["hmtx"][name] = (0, g.xMin)
    order = font.getGlyphOrder()
    if name not in order:
        font.setGlyphOrder(order + [name])
    for table in font["cmap"].tables:
        if table.isUnicode():
            table.cmap[code] = name


def build_mark_font(path):
    """Write the mark test font to ``path`` (see the module docstring); returns path."""
    from fontTools.feaLib.builder import addOpenTypeFeaturesFromString

    font = TTFont(default_font_path())
    _add_mark(font, "acutecomb", "acute", 0x301)
    _add_mark(font, "gravecomb", "grave", 0x300)
    for table in font["cmap"].tables:  # e + U+0301 must not compose to eacute
        if table.isUnicode():
            for code in (0xE9, 0xF3):
                table.cmap.pop(code, None)
    _, ay0, _, ay1 = bounds(font, "acutecomb")
    anchors = []
    for base in ("e", "o"):
        bx0, _, bx1, by1 = bounds(font, base)
        anchors.append("pos base %s <anchor %d %d> mark @TOP;"
                       % (base, round((bx0 + bx1) / 2), round(by1 + 40)))
    fea = """
    languagesystem DFLT dflt;
    languagesystem latn dflt;
    markClass [acutecomb gravecomb] <anchor 0 %d> @TOP;
    markClass [acutecomb gravecomb] <anchor 0 %d> @TOP2;
    feature mark { %s } mark;
    feature mkmk { pos mark acutecomb <anchor 0 %d> mark @TOP2; } mkmk;
    table GDEF { GlyphClassDef , , [acutecomb gravecomb], ; } GDEF;
    """ % (round(ay0), round(ay0), " ".join(anchors), round(ay1 + 30))
    for tag in ("GPOS", "GDEF", "GSUB"):
        if tag in font:
            del font[tag]
    addOpenTypeFeaturesFromString(font, fea)
    font.save(str(path))
    return path


def widen_glyf(font, factor=WIDE):
    """Scale a TrueType font's outlines, component offsets and advances by ``factor``
    in x, in place, rounded to integers: the wide master of the test fonts."""
    glyf, hmtx = font["glyf"], font["hmtx"]
    for name in font.getGlyphOrder():
        g = glyf[name]
        if g.isComposite():
            for c in g.components:
                c.x = int(round(c.x * factor))
        elif g.numberOfContours > 0:
            coords = np.array(g.coordinates, float)
            coords[:, 0] = np.round(coords[:, 0] * factor)
            g.coordinates = type(g.coordinates)([tuple(map(int, p)) for p in coords])
            g.recalcBounds(glyf)
        adv, lsb = hmtx[name]
        hmtx[name] = (int(round(adv * factor)), int(round(lsb * factor)))
    return font


def build_variable_font(folder):
    """Write the two-master variable font into ``folder``; returns its path."""
    from fontTools.designspaceLib import AxisDescriptor, DesignSpaceDocument, SourceDescriptor
    from fontTools.varLib import build

    regular = folder / "Var-Regular.ttf"
    wide = folder / "Var-Wide.ttf"
    font = TTFont(default_font_path())
    for tag in ("GPOS", "GSUB", "GDEF", "STAT"):
        if tag in font:
            del font[tag]
    font.save(str(regular))
    widen_glyf(font)
    font.save(str(wide))
    doc = DesignSpaceDocument()
    axis = AxisDescriptor()
    axis.tag, axis.name, axis.minimum, axis.default, axis.maximum = "wght", "Weight", 400, 400, 700
    doc.addAxis(axis)
    for path, wght in ((regular, 400), (wide, 700)):
        src = SourceDescriptor()
        src.path, src.location = str(path), {"Weight": wght}
        doc.addSource(src)
    var, _, _ = build(doc)
    out = folder / "Var[wght].ttf"
    var.save(str(out))
    return out


def skeleton_line(glyph, *points, closed=False):
    """A skeleton contour of lines through ``points`` (open: its first point a move)."""
    pen = glyph.getPointPen()
    pen.beginPath()
    for i, p in enumerate(points):
        pen.addPoint(p, "line" if (i or closed) else "move")
    pen.endPath()


def hershey_like():
    """A ufoLib2 skeleton font like the Hershey single-stroke sans: open lines, a
    dot, a closed loop, a glyph without unicode, a zero-width mark, a float
    unitsPerEm, minimal font info; nothing that needs ufo2ft's feature writers."""
    import ufoLib2

    font = ufoLib2.Font()
    font.info.familyName, font.info.styleName = "Hershey Like", "Regular"
    font.info.unitsPerEm = 1000.0
    font.info.ascender, font.info.descender = 800, -200
    font.info.capHeight, font.info.xHeight = 700, 500
    for name, code, width in (("A", 0x41, 567.0), ("period", 0x2E, 200), ("O", 0x4F, 600),
                              ("l", 0x6C, 250.5), ("dotless", None, 300),
                              ("gravecomb", 0x300, 0)):
        g = font.newGlyph(name)
        g.width = width
        if code is not None:
            g.unicodes = [code]
        if name == "A":
            skeleton_line(g, (378, 662), (126, 0))
            skeleton_line(g, (378, 662), (630, 0))
            skeleton_line(g, (220, 220), (536, 220))
        elif name == "period":
            skeleton_line(g, (100, 0))                     # a dot: one point
        elif name == "O":
            skeleton_line(g, (100, 100), (500, 100), (500, 600), (100, 600), closed=True)
        elif name == "gravecomb":
            skeleton_line(g, (-150, 700), (-80, 600))
        else:
            skeleton_line(g, (125, 0), (125.5, 700))
    font.lib["public.glyphOrder"] = ["A", "O", "l"]   # the rest sorted by name
    return font

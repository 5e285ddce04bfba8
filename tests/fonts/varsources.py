"""Small brush sources with mark positioning, built from the bundled Noto Sans with
fontTools (no download): the static mark font of tests/fontfixtures.py, a CFF
(.otf) copy of it, and two-master variable fonts (axis wght 400-700, the wght=700
master's outlines, advances and GPOS anchors scaled 1.25x horizontally) as
glyf/gvar and as CFF2, compiled by varLib from those masters (so their anchors
vary with wght)."""

from tests.fontfixtures import build_mark_font, widen_glyf

WIDE = 1.25
GLYPHS = ["o", "e", "n", "acutecomb"]


def _subset(font, glyphs):
    from fontTools import subset

    opts = subset.Options()
    opts.layout_features = ["*"]
    opts.glyph_names = True
    opts.notdef_outline = True
    opts.name_IDs = ["*"]
    sub = subset.Subsetter(opts)
    sub.populate(glyphs=glyphs)
    sub.subset(font)
    return font


def mark_font(folder):
    """The static mark font cut to :data:`GLYPHS` (and .notdef, space): a path."""
    from fontTools.ttLib import TTFont

    full = build_mark_font(folder / "MarkFull.ttf")
    font = _subset(TTFont(str(full)), GLYPHS + ["space"])
    out = folder / "Mark.ttf"
    font.save(str(out))
    return out


def to_cff(font):
    """A glyf font turned CFF in place (every quadratic raised to a cubic, exact)."""
    from fontTools.fontBuilder import FontBuilder
    from fontTools.pens.reverseContourPen import ReverseContourPen
    from fontTools.pens.t2CharStringPen import T2CharStringPen

    gs = font.getGlyphSet()
    charstrings = {}
    for name in font.getGlyphOrder():
        pen = T2CharStringPen(gs[name].width, gs)
        gs[name].draw(ReverseContourPen(pen))   # CFF: outer contours counter-clockwise
        charstrings[name] = pen.getCharString()
    for tag in ("glyf", "loca", "gvar", "fpgm", "prep", "cvt ", "gasp"):
        if tag in font:
            del font[tag]
    fb = FontBuilder(font=font)
    fb.isTTF = False
    fb.setupCFF("MarkCFF-Regular", {"FullName": "Mark CFF"}, charstrings, {})
    font["maxp"].tableVersion = 0x00005000
    font.sfntVersion = "OTTO"
    post = font["post"]
    post.formatType = 3.0
    return font


def _wide(font, scale=(WIDE, 1.0), only=None):
    """The wght=700 master: outlines, advances and GPOS anchors scaled by ``scale``
    (x, y; default 1.25 x), rounded to integers; with ``only`` (glyph names) the
    other glyphs' outlines are scaled uniformly, by x's scale in y too."""
    import numpy as np

    from morph.fonts.tables import _lookup_subtables

    sx, sy = scale
    widen_glyf(font, sx)
    if sy != 1.0:
        glyf = font["glyf"]
        for name in font.getGlyphOrder():
            g = glyf[name]
            if g.numberOfContours > 0:
                c = np.array(g.coordinates, float)
                c[:, 1] = np.round(c[:, 1] * (sy if only is None or name in only else sx))
                g.coordinates = type(g.coordinates)([tuple(map(int, p)) for p in c])
                g.recalcBounds(glyf)
    seen = set()
    for st in _lookup_subtables(font):
        for a in _anchors(st):
            if id(a) not in seen:
                seen.add(id(a))
                a.XCoordinate = int(round(a.XCoordinate * sx))
                a.YCoordinate = int(round(a.YCoordinate * sy))
    return font


def _anchors(st):
    kind = type(st).__name__
    recs = []
    if kind == "MarkBasePos":
        recs = [r.MarkAnchor for r in st.MarkArray.MarkRecord] + \
            [a for r in st.BaseArray.BaseRecord for a in r.BaseAnchor]
    elif kind == "MarkMarkPos":
        recs = [r.MarkAnchor for r in st.Mark1Array.MarkRecord] + \
            [a for r in st.Mark2Array.Mark2Record for a in r.Mark2Anchor]
    return [a for a in recs if a is not None]


def variable_mark_font(folder, cff2=False, scale=(WIDE, 1.0), only=None):
    """The two-master variable mark font (glyf/gvar, or CFF2): a path; the wght=700
    master is the Regular one scaled by ``scale`` (x, y; with ``only``, the other
    glyphs uniformly by x's)."""
    from fontTools.designspaceLib import AxisDescriptor, DesignSpaceDocument, SourceDescriptor
    from fontTools.ttLib import TTFont
    from fontTools.varLib import build

    base = mark_font(folder)
    suffix = ".otf" if cff2 else ".ttf"
    paths = []
    for style, wide in (("Regular", False), ("Wide", True)):
        font = TTFont(str(base))
        if wide:
            _wide(font, scale, only)
        if cff2:
            to_cff(font)
        p = folder / ("Mark-%s%s" % (style, suffix))
        font.save(str(p))
        paths.append(p)
    doc = DesignSpaceDocument()
    axis = AxisDescriptor()
    axis.tag, axis.name, axis.minimum, axis.default, axis.maximum = "wght", "Weight", 400, 400, 700
    doc.addAxis(axis)
    for path, wght in zip(paths, (400, 700)):
        src = SourceDescriptor()
        src.path, src.location = str(path), {"Weight": wght}
        doc.addSource(src)
    var, _, _ = build(doc, optimize=False)
    out = folder / ("MarkVar" + suffix)
    out = out.with_name("%s-%g-%g%s%s" % (out.stem, scale[0], scale[1],
                                           "-" + "-".join(only) if only else "", out.suffix)) \
        if tuple(scale) != (WIDE, 1.0) else out
    var.save(str(out))
    return out


def source_instance(path, location):
    """The source's own instance at a user location (its glyph set), fontTools'
    instancer; a static font's glyph set for an empty location."""
    from fontTools.ttLib import TTFont
    from fontTools.varLib import instancer

    font = TTFont(str(path))
    if "fvar" not in font:
        return font
    return instancer.instantiateVariableFont(font, location)


def mark_anchor(font, base, mark="acutecomb"):
    """((x, y) of the base's anchor, (x, y) of the mark's) of the first mark-to-base
    lookup attaching ``mark`` to ``base``, in a static font."""
    from morph.fonts.tables import _lookup_subtables

    for st in _lookup_subtables(font):
        if type(st).__name__ != "MarkBasePos":
            continue
        if base in st.BaseCoverage.glyphs and mark in st.MarkCoverage.glyphs:
            mrec = st.MarkArray.MarkRecord[st.MarkCoverage.glyphs.index(mark)]
            brec = st.BaseArray.BaseRecord[st.BaseCoverage.glyphs.index(base)]
            b = brec.BaseAnchor[mrec.Class]
            return ((b.XCoordinate, b.YCoordinate),
                    (mrec.MarkAnchor.XCoordinate, mrec.MarkAnchor.YCoordinate))
    return None

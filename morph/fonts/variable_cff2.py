"""CFF2 output of a brushed variable font: the fitted cubics of every master as
blended CFF2 charstrings, the advances as HVAR.

Each master's contours are drawn with their points rounded to integers (as the
TrueType output's are), merged into one charstring per glyph by fontTools'
``CFF2CharStringMergePen`` over the glyph's own masters' grid model
(:func:`morph.fonts.variable_grid.grid_model`: integer deltas, every master
exactly its own rounded outline; the charstring's coordinates are relative, so a
master reproduced within a rounding per coordinate would carry that error along
the contour), into a CFF2 table whose variation store holds every glyph's
regions, one VarData per distinct set of glyph masters (the charstring's
``vsindex`` picks it).  The
overlapping contours need no flag: CFF2 charstrings are filled nonzero.  The
advances vary through HVAR (CFF2 has no phantom points), built by fontTools
varLib's HVAR builder from the same model.
"""

import numpy as np

__all__ = ["write_cff2"]

#: tables of TrueType outlines and hinting a CFF2 font has no use for
_TRUETYPE = ("glyf", "loca", "gvar", "CFF ", "CFF2", "VORG", "fpgm", "prep", "cvt ",
             "cvar", "HVAR", "VVAR", "hdmx", "LTSH", "VDMX", "DSIG")


def write_cff2(font, plan, results, moved, widths):
    """Replace the outlines of ``font`` by a CFF2 table and HVAR.

    ``plan``: the brush's plan (``plan.masters(name)``: a glyph's own fitted
    masters, their locations, source masters and grid model); ``results``: (name,
    per master cubic contours or None, seconds) of every glyph; ``moved``: per
    brushed glyph, (x shift, advance growth) at each of its masters; ``widths(s,
    name)``: the advance at source master ``s``.  Every glyph's blends run over its
    own masters' regions: one VarData per distinct set of masters, chosen by the
    charstring's ``vsindex``.  Returns the brushed glyphs' default shifts ((x, 0)
    each) for the anchors."""
    contours = {name: c for name, c, _ in results if c is not None}
    charstrings, advances, lsbs, models = {}, {}, {}, {}
    for name in font.getGlyphOrder():
        masters = plan.masters(name)
        n = len(masters.locs)
        shift = moved.get(name, [(0.0, 0)] * n)
        per = contours.get(name)
        charstrings[name], lsbs[name] = _charstring(name, per, [s for s, _ in shift],
                                                    masters.model)
        _check_length(name, charstrings[name], n)
        models[name] = masters.model
        advances[name] = [int(round(widths(masters.source(m), name))) + shift[m][1]
                          for m in range(n)]
    _cff2_table(font, charstrings, models, plan.tags)
    for name in font.getGlyphOrder():
        font["hmtx"][name] = (advances[name][0], lsbs[name])
    _hvar(font, models, advances, plan.tags)
    return {name: (shift[0][0], 0.0) for name, shift in moved.items()}


def _charstring(name, per, shifts, model):
    """(blended CFF2 charstring, the default master's left side bearing) of one
    glyph from its cubic contours at every master (None: no contours)."""
    from fontTools.pens.boundsPen import BoundsPen
    from fontTools.varLib.cff import CFF2CharStringMergePen

    pen = CFF2CharStringMergePen([], name, len(model.locations), 0, roundTolerance=1e-6)
    bounds = BoundsPen(None)
    for m in range(len(model.locations)):
        if m:
            pen.restart(m)
        for loop in (per[m] if per is not None else []):
            pts = np.round(np.asarray(loop, float) + np.array([shifts[m], 0.0])).astype(int)
            pts = pts.tolist()
            for p in ([pen, bounds] if m == 0 else [pen]):
                p.moveTo(tuple(pts[0][0]))
                for c in pts:
                    p.curveTo(tuple(c[1]), tuple(c[2]), tuple(c[3]))
                p.closePath()
    cs = pen.getCharString(var_model=model, optimize=True)
    return cs, (int(bounds.bounds[0]) if bounds.bounds else 0)


#: the longest charstring readers take (the Type 2 charstring limit; ots-sanitize
#: refuses a CFF2 font with a longer one)
MAX_CHARSTRING = 65535


def _check_length(name, charstring, masters):
    """Raise MorphError when glyph ``name``'s blended charstring is longer than
    :data:`MAX_CHARSTRING` bytes (every coordinate carries a delta per master
    beyond the default: a glyph with many masters can pass it)."""
    from fontTools.misc.psCharStrings import T2CharString

    from ..errors import MorphError

    probe = T2CharString(program=list(charstring.program))  # the font's is compiled later
    probe.compile(isCFF2=True)
    size = len(probe.bytecode)
    if size > MAX_CHARSTRING:
        raise MorphError("glyph %r needs %d masters and a CFF2 charstring of %d bytes, more "
                         "than the %d a reader takes; write a TrueType variable font (.ttf) "
                         "instead" % (name, masters, size, MAX_CHARSTRING))


def _region_key(support):
    return tuple(sorted((t, tuple(float(v) for v in r)) for t, r in support.items()))


def _cff2_table(font, charstrings, models, tags):
    """The font's outline tables replaced by a CFF2 table of ``charstrings``; its
    variation store holds every glyph model's regions, one VarData per distinct
    model (its regions in the model's order), each charstring prefixed by its
    model's ``vsindex`` (none for VarData 0); maxp 0.5, post format 2 (the glyph
    names kept: CFF2 has none of its own)."""
    from fontTools.cffLib import VarStoreData
    from fontTools.fontBuilder import FontBuilder
    from fontTools.varLib.builder import buildVarData, buildVarRegionList, buildVarStore

    for tag in _TRUETYPE:
        if tag in font:
            del font[tag]
    regions, datas, vsindex = {}, [], {}
    for name in font.getGlyphOrder():
        model = models[name]
        if id(model) not in vsindex:
            keys = [_region_key(s) for s in model.supports[1:]]
            for k, s in zip(keys, model.supports[1:]):
                regions.setdefault(k, (len(regions), s))
            vsindex[id(model)] = len(datas)
            datas.append(buildVarData([regions[k][0] for k in keys], None, optimize=False))
        k = vsindex[id(model)]
        if k:
            charstrings[name].program[:0] = [k, "vsindex"]
    fb = FontBuilder(font=font)
    fb.isTTF = False
    fb.setupCFF2(charstrings)
    region_list = buildVarRegionList([s for _, s in sorted(regions.values(),
                                                           key=lambda r: r[0])], tags)
    store = VarStoreData(otVarStore=buildVarStore(region_list, datas))
    top = font["CFF2"].cff.topDictIndex[0]
    top.VarStore = store
    for fd in top.FDArray:
        fd.Private.vstore = store
    font["maxp"].tableVersion = 0x00005000
    post = font["post"]
    post.formatType = 2.0
    post.extraNames, post.mapping = [], {}
    font.sfntVersion = "OTTO"


def _hvar(font, models, advances, tags):
    """HVAR of the advances at each glyph's masters, over its own model (varLib's
    builder: a direct store when every glyph uses the one model, else rows mapped per
    glyph)."""
    from fontTools import varLib

    def metrics():
        return {n: models[n].getDeltasAndSupports(a, round=round)
                for n, a in advances.items()}, {}

    varLib._add_VHVAR(font, tags, varLib.HVAR_FIELDS, metrics)

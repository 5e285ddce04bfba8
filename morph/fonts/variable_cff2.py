"""CFF2 output of a brushed variable font: the fitted cubics of every master as
blended CFF2 charstrings, the advances as HVAR.

Each master's contours are drawn with their points rounded to integers (as the
TrueType output's are), merged into one charstring per glyph by fontTools'
``CFF2CharStringMergePen`` over the masters' grid model
(:func:`morph.fonts.variable_grid.grid_model`: integer deltas, every master
exactly its own rounded outline; the charstring's coordinates are relative, so a
master reproduced within a rounding per coordinate would carry that error along
the contour), into a CFF2 table whose one
variation store holds the model's regions (vsindex 0 for every glyph).  The
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

    ``plan``: the brush's fitted masters (``locs`` over ``tags``, ``owners``: each
    master's source master); ``results``: (name, per master cubic contours or None,
    seconds) of every glyph; ``moved``: per brushed glyph, (x shift, advance growth)
    at every master; ``widths``: per source master, the advances.  Returns the
    brushed glyphs' default shifts ((x, 0) each) for the anchors."""
    from .variable_grid import grid_model

    model = grid_model(plan.locs, plan.tags)
    contours = {name: c for name, c, _ in results if c is not None}
    n = len(plan.locs)
    charstrings, advances, lsbs = {}, {}, {}
    for name in font.getGlyphOrder():
        shift = moved.get(name, [(0.0, 0)] * n)
        per = contours.get(name)
        charstrings[name], lsbs[name] = _charstring(name, per, [s for s, _ in shift], model)
        advances[name] = [int(round(widths[o][name])) + shift[m][1]
                          for m, o in enumerate(plan.owners)]
    _cff2_table(font, charstrings, model)
    for name in font.getGlyphOrder():
        font["hmtx"][name] = (advances[name][0], lsbs[name])
    _hvar(font, model, advances, plan.tags)
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


def _cff2_table(font, charstrings, model):
    """The font's outline tables replaced by a CFF2 table of ``charstrings`` with the
    model's regions as its variation store; maxp 0.5, post format 2 (the glyph names
    kept: CFF2 has none of its own)."""
    from fontTools.fontBuilder import FontBuilder

    for tag in _TRUETYPE:
        if tag in font:
            del font[tag]
    fb = FontBuilder(font=font)
    fb.isTTF = False
    fb.setupCFF2(charstrings, regions=model.supports[1:])
    font["maxp"].tableVersion = 0x00005000
    post = font["post"]
    post.formatType = 2.0
    post.extraNames, post.mapping = [], {}
    font.sfntVersion = "OTTO"


def _hvar(font, model, advances, tags):
    """HVAR of the advances at every master (varLib's builder: a direct store when
    every glyph uses the one model)."""
    from fontTools import varLib

    def metrics():
        return {n: model.getDeltasAndSupports(a, round=round) for n, a in advances.items()}, {}

    varLib._add_VHVAR(font, tags, varLib.HVAR_FIELDS, metrics)

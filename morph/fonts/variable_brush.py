"""Variable TrueType fonts brushed keeping their axes: every master of the source
(and intermediate ones on its master grid) ⊕ an elliptical nib, as untrimmed
overlapping contours fitted with common breaks across the masters
(:func:`morph.compatible.region_elements`), written into the glyf/gvar of a copy of
the source.  The error budget and the overlap flags are those of
:mod:`morph.fonts.variable`."""

import time

import numpy as np

from ..compatible import Ellipse, fit_elements, region_elements
from ..errors import MorphError
from .variable import CU2QU_SHARE, FIT_SHARE, set_overlap_flags

__all__ = ["brush_variable"]

def _master_locations(font, split=1):
    """Normalized locations of the brushed masters of a glyf/gvar font: the default,
    the peak of every region its glyph variations use, and with ``split`` > 0 the
    grid between them refined 2**split times along every axis (the source's own
    interpolation gives the skeleton there; the nib part does not interpolate
    between distant masters: a normal that turns between two masters moves its nib
    point along an arc, not a chord)."""
    import itertools

    peaks = set()
    for variations in font["gvar"].variations.values():
        for v in variations:
            peaks.add(tuple(sorted((tag, float(t[1])) for tag, t in v.axes.items())))
    tags = [a.axisTag for a in font["fvar"].axes]
    locs = [{t: 0.0 for t in tags}] + [{**{t: 0.0 for t in tags}, **dict(p)}
                                       for p in sorted(peaks)]
    if split > 0:
        values = {t: sorted({loc[t] for loc in locs}) for t in tags}
        grid = {}
        for t in tags:
            vs = values[t]
            fine = set(vs)
            for a, b in zip(vs[:-1], vs[1:]):
                fine.update(a + (b - a) * k / 2 ** split for k in range(1, 2 ** split))
            grid[t] = sorted(fine)
        seen = {tuple(loc[t] for t in tags) for loc in locs}
        for combo in itertools.product(*(grid[t] for t in tags)):
            if combo not in seen:
                seen.add(combo)
                locs.append(dict(zip(tags, combo)))
    return locs


def _region_loops(glyph_set, name):
    """A glyph's contours at one master as closed loops of cartesian pieces, turned
    counter-clockwise for the outer ones (TrueType draws them clockwise)."""
    from ..parse.pens import record_contours

    contours = record_contours(glyph_set[name].draw, "glyph %r" % name, glyph_set)
    loops = []
    for c in contours:
        pieces = [np.asarray(p, float) for p in c.pieces]
        pieces = [p[:, :2] / p[:, 2:] if p.shape[1] == 3 else p for p in pieces]
        if pieces and np.any(pieces[-1][-1] != pieces[0][0]):
            pieces.append(np.array([pieces[-1][-1], pieces[0][0]]))
        if pieces:
            loops.append([p[::-1] for p in reversed(pieces)])
    return loops


def _brush_glyph_job(args):
    """(name, per-master quadratic contours or None, CPU s) of one glyph ⊕ nib at
    every master, converted to quadratics compatibly (cu2qu on the masters' curves
    together)."""
    from fontTools.cu2qu import curves_to_quadratic

    name, loops_by_master, nib, fit_tol, q_tol = args
    t0 = time.process_time()
    if not loops_by_master[0]:
        return name, None, 0.0
    fits = fit_elements(region_elements(loops_by_master, "glyph %r" % name),
                        [nib] * len(loops_by_master), list(range(len(loops_by_master))),
                        fit_tol)
    out = [[] for _ in fits]
    for k in range(len(fits[0])):
        per = [[] for _ in fits]
        for j in range(len(fits[0][k])):
            curves = [[tuple(p) for p in fits[m][k][j]] for m in range(len(fits))]
            splines = curves_to_quadratic(curves, [q_tol] * len(curves))
            for m, s in enumerate(splines):
                per[m].append(s)
        for m in range(len(fits)):
            out[m].append(per[m])
    return name, out, time.process_time() - t0


def brush_variable(src, out_path, nib, glyphs=None, tol=0.5, family_name=None, jobs=1,
                   progress=None, split=1):
    """Brush a variable TrueType font keeping its axes: every master of every chosen
    glyph ⊕ the nib, as untrimmed overlapping contours fitted compatibly across the
    masters (:func:`morph.compatible.region_elements`), converted to quadratics with
    cu2qu on all masters at once; the glyf/gvar of a copy of the source are
    replaced (its layout, names, STAT and avar kept; the advance variations carried
    by gvar's phantom points, HVAR dropped), the outlines shifted right by the nib's
    left extent, advances grown by its width, GPOS anchors moved along.

    ``src``: a variable ``.ttf`` (glyf/gvar); ``nib``: (width, height, angle);
    ``glyphs``: glyph names (None: every glyph with contours; composites are
    decomposed); ``tol``: font units (fit FIT_SHARE, quadratics CU2QU_SHARE, the rest
    the masters' own interpolation of the nib part, measured, not bounded: a
    source's masters are not a nib scale); ``split``: intermediate masters, the
    source's master grid refined 2**split times per axis (:func:`_master_locations`;
    Source Serif 4 with split 1: 25 masters instead of 9).  Returns a dict: ``masters``
    (normalized locations), ``glyphs``, ``fit_seconds``, ``font``.

    Raises:
        MorphError: not a glyf/gvar variable font; IncompatibleMasters: cannot happen
            for a valid variable font (its masters share their points).
    """
    from fontTools.ttLib import TTFont
    from fontTools.varLib.models import VariationModel

    from .jobs import run_jobs
    from .tables import move_anchors, rename_family, save_font

    font = TTFont(str(src))
    if "fvar" not in font or "gvar" not in font or "glyf" not in font:
        raise MorphError("%s is not a TrueType variable font (glyf/gvar)" % src)
    nib = Ellipse(*map(float, nib))
    locs = _master_locations(font, split)
    tags = [a.axisTag for a in font["fvar"].axes]
    sets = [font.getGlyphSet(location=loc, normalized=True) for loc in locs]
    glyf = font["glyf"]
    names = [n for n in font.getGlyphOrder()
             if (glyphs is None or n in glyphs) and glyf[n].numberOfContours != 0]
    work = [(n, [_region_loops(gs, n) for gs in sets], nib, FIT_SHARE * tol,
             CU2QU_SHARE * tol) for n in names]
    report = None if progress is None else (lambda k, r: progress(r[0]))
    results = run_jobs(_brush_glyph_job, work, jobs=jobs, progress=report)
    model = VariationModel(locs, tags)
    hx = float(nib.extent()[2])
    shifts = {name: _write_glyph(font, model, sets, name, contours, hx)
              for name, contours, _ in results if contours is not None}
    if "HVAR" in font:
        del font["HVAR"]
    move_anchors(font, shifts)
    if family_name:
        rename_family(font, family_name)
    set_overlap_flags(font)
    save_font(font, out_path)
    return {"masters": locs, "glyphs": len(shifts),
            "fit_seconds": sum(r[2] for r in results), "font": font}


def _write_glyph(font, model, sets, name, contours, hx):
    """Glyph ``name``'s brushed quadratic contours of every master written into the
    glyf (default master), hmtx and gvar (the other masters' deltas by ``model``,
    advances through the phantom points) of ``font``; the outlines shift right by
    the nib's left extent ``hx`` (a zero-width mark left by the nib's width, keeping
    advance 0).  Returns the shift (x, y) for the anchors."""
    from fontTools.pens.ttGlyphPen import TTGlyphPen
    from fontTools.ttLib.tables.TupleVariation import TupleVariation

    glyf, gvar, hmtx = font["glyf"], font["gvar"], font["hmtx"]
    grow = int(round(2 * hx))
    width0 = hmtx[name][0]
    shift = hx - (grow if width0 == 0 else 0)
    coords = []
    for m, per in enumerate(contours):
        pen = TTGlyphPen(None)
        for splines in per:
            pen.moveTo(_rnd(splines[0][0], shift))
            for s in splines:
                pen.qCurveTo(*[_rnd(p, shift) for p in s[1:]])
            pen.closePath()
        g = pen.glyph(dropImpliedOnCurves=False)
        adv = sets[m][name].width + (grow if width0 else 0)
        pts = list(g.coordinates) + [(0, 0), (adv, 0), (0, 0), (0, 0)]
        coords.append(np.array(pts, float))
        if m == 0:
            glyph0, adv0 = g, adv
    glyf[name] = glyph0
    glyph0.recalcBounds(glyf)
    hmtx[name] = (int(adv0), glyph0.xMin)
    deltas, supports = model.getDeltas(coords), model.supports
    gvar.variations[name] = [TupleVariation(sup, [tuple(map(int, np.round(p))) for p in d])
                             for d, sup in zip(deltas[1:], supports[1:])
                             if np.any(np.round(d) != 0)]
    return (shift, 0.0)


def _rnd(p, shift):
    return (int(round(p[0] + shift)), int(round(p[1])))

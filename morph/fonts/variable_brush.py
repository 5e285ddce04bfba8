"""Variable brushed fonts: a compiled font's glyphs ⊕ elliptical nibs as a variable
TrueType font, with the source's axes (a variable source) and an optional nib axis.

Every master of the source (and intermediate ones on its master grid: the nib part
of distant masters does not interpolate) is brushed by every nib master, as untrimmed
overlapping contours fitted with common breaks across all of them
(:func:`morph.compatible.region_elements`), converted to quadratics compatibly
(cu2qu on all masters' curves at once) and written into the glyf/gvar of a copy of
the source, the glyph variations computed by fontTools' ``VariationModel`` over the
masters' locations.  The error budget and the overlap flags are those of
:mod:`morph.fonts.variable`.

Sources:

- a variable TrueType font (glyf/gvar): its axes, avar, STAT, named instances and
  layout are kept; its masters are the peaks of its gvar regions;
- a variable CFF2 font: read through fontTools' glyph set at each master location
  (the peaks of its CFF2 variation regions); the output is TrueType: the CFF2 table
  is replaced by glyf/loca/gvar (every glyph converted compatibly, the ones not
  brushed too), maxp/head/post made TrueType's;
- a static font (.ttf or .otf) with a nib axis: fvar, gvar and STAT are added.

The nib axis (``nib_max``) is :func:`morph.fonts.variable.nib_axis`'s (NIBW / NIBP),
appended to the source's axes: every region of the source's item variation stores
(GDEF, MVAR, BASE) gets the new axis as "not involved", named instances sit at its
default, avar maps it by identity.  Two disks (a round nib that only grows) with
``grade`` make the registered grade axis ``GRAD`` instead: user values are the
growth of the disk's diameter in units per 1000 em (0 at the ``--nib`` disk), the
advances and the outlines' shift are those of the default disk at every position
(a disk thickens every stroke equally in every direction, like a weight change,
and with the advances fixed no line of text reflows: what Google's axis registry
defines GRAD as, "a finesse adjustment of the weight without changing the width").

Anchors (GPOS mark, mark-to-mark, ligature, cursive and GDEF carets) move with the
outlines at every master: by the default master's shift, and where the shift
varies along the nib axis (NIBW / NIBP: the nib's left extent; a zero-width mark by
minus the width) by a variation of its own (a format 3 anchor whose device table
indexes deltas in GDEF's item variation store, merged with the anchor's own
variation of the source's axes).
"""

import time
from dataclasses import dataclass

import numpy as np

from ..compatible import Ellipse, fit_elements, region_elements
from ..errors import MorphError, ParseError
from .variable import BLEND_SHARE, CU2QU_SHARE, FIT_SHARE, NibAxis, axis_masters, nib_axis, \
    set_overlap_flags

__all__ = ["brush_variable", "grade_axis", "source_locations"]


def grade_axis(nib_min, nib_max, upm):
    """The GRAD :class:`NibAxis` between two disks (the second larger): user value the
    growth of the diameter in units per 1000 em; None when the nibs are not two
    growing disks."""
    a, b = Ellipse(*map(float, nib_min)), Ellipse(*map(float, nib_max))
    if a.width != a.height or b.width != b.height or not b.width > a.width:
        return None
    grow = (b.width - a.width) * 1000.0 / upm
    return NibAxis("GRAD", "Grade", 0.0, round(grow, 3), a, b)


def _region_peaks(store):
    """Peaks (tag index -> peak) of the regions of an item variation store."""
    out = set()
    for region in store.VarRegionList.Region:
        out.add(tuple((k, float(ax.PeakCoord)) for k, ax in enumerate(region.VarRegionAxis)
                      if ax.PeakCoord != 0))
    return out


def source_locations(font, split=1):
    """Normalized locations of the brushed masters of a variable font (glyf/gvar or
    CFF2): the default, the peak of every region its glyph variations use, and with
    ``split`` > 0 the grid between them refined 2**split times along every axis (the
    source's own interpolation gives the glyphs there; the nib part does not
    interpolate between distant masters: a normal that turns between two masters
    moves its nib point along an arc, not a chord).  ``[{}]`` for a static font."""
    import itertools

    if "fvar" not in font:
        return [{}]
    tags = [a.axisTag for a in font["fvar"].axes]
    peaks = set()
    if "gvar" in font:
        for variations in font["gvar"].variations.values():
            for v in variations:
                peaks.add(tuple(sorted((tag, float(t[1])) for tag, t in v.axes.items())))
    elif "CFF2" in font:
        store = font["CFF2"].cff.topDictIndex[0].VarStore
        if store is not None:
            peaks = {tuple(sorted((tags[k], p) for k, p in peak))
                     for peak in _region_peaks(store.otVarStore)}
    locs = [{t: 0.0 for t in tags}] + [{**{t: 0.0 for t in tags}, **dict(p)}
                                       for p in sorted(peaks) if p]
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
    """A glyph's contours at one master as closed loops of cartesian pieces, in the
    font's direction (:func:`_counter_clockwise` turns them)."""
    from ..parse.pens import record_contours

    contours = record_contours(glyph_set[name].draw, "glyph %r" % name, glyph_set)
    loops = []
    for c in contours:
        pieces = [np.asarray(p, float) for p in c.pieces]
        pieces = [p[:, :2] / p[:, 2:] if p.shape[1] == 3 else p for p in pieces]
        if pieces and np.any(pieces[-1][-1] != pieces[0][0]):
            pieces.append(np.array([pieces[-1][-1], pieces[0][0]]))
        if pieces:
            loops.append(pieces)
    return loops


def _signed_area(loops):
    """Signed area of loops of pieces, their control polygons' (the sign of a glyph's
    total area is its outer contours' direction)."""
    total = 0.0
    for loop in loops:
        pts = np.vstack([p[:-1] for p in loop])
        x, y = pts[:, 0], pts[:, 1]
        total += 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return total


def _counter_clockwise(loops_by_master):
    """Loops turned so that outer ones run counter-clockwise: reversed when the
    glyph's area at the default master is negative (TrueType draws outer contours
    clockwise, CFF counter-clockwise; a font that does not follow its convention
    is read by the sign of the area)."""
    if _signed_area(loops_by_master[0]) >= 0:
        return loops_by_master
    return [[[p[::-1] for p in reversed(loop)] for loop in loops] for loops in loops_by_master]


def _to_quadratic(fits, q_tol):
    """Per master contours of quadratic splines, converted compatibly (cu2qu on every
    master's curves together)."""
    from fontTools.cu2qu import curves_to_quadratic

    out = [[] for _ in fits]
    for k in range(len(fits[0])):
        per = [[] for _ in fits]
        for j in range(len(fits[0][k])):
            curves = [[tuple(p) for p in fits[m][k][j]] for m in range(len(fits))]
            for m, s in enumerate(curves_to_quadratic(curves, [q_tol] * len(curves))):
                per[m].append(s)
        for m in range(len(fits)):
            out[m].append(per[m])
    return out


def _cubic(piece):
    """A line, quadratic or cubic (n+1, 2) as a cubic (4, 2), exact."""
    from ..compatible import _to_cubic

    return _to_cubic(piece)


def _brush_glyph_job(args):
    """(name, per fitted master quadratic contours or None, CPU s) of one glyph: its
    loops at every source master ⊕ the nib of every fitted master (``nibs``, the
    source master of each: ``owners``), or with ``nibs`` None the glyph itself at
    every fitted master (a glyph converted, not brushed)."""
    name, loops_by_source, nibs, owners, fit_tol, q_tol = args
    t0 = time.process_time()
    if not loops_by_source[0]:
        return name, None, 0.0
    loops_by_source = _counter_clockwise(loops_by_source)
    if nibs is None:
        fits = [[np.array([_cubic(p) for p in loop]) for loop in loops_by_source[o]]
                for o in owners]
    else:
        fits = fit_elements(region_elements(loops_by_source, "glyph %r" % name), nibs, owners,
                            fit_tol)
    return name, _to_quadratic(fits, q_tol), time.process_time() - t0


def _open(src):
    from fontTools.ttLib import TTFont

    if hasattr(src, "getGlyphSet"):
        return src
    try:
        font = TTFont(str(src))
        font["head"]
    except Exception as exc:  # fontTools raises many types for garbage input
        raise ParseError("cannot read font %s: %s" % (src, exc), str(src)) from exc
    return font


def brush_variable(src, out_path, nib, glyphs=None, tol=0.5, family_name=None, jobs=1,
                   progress=None, split=1, nib_max=None, grade=True):
    """Brush a font into a variable TrueType font: every master of every chosen glyph
    ⊕ the nib (and with ``nib_max`` every nib master of the nib axis), as untrimmed
    overlapping contours fitted compatibly across the masters, converted to
    quadratics with cu2qu on all masters at once, written into the glyf/gvar of a
    copy of the source (its layout, names, STAT and avar kept; the advance variations
    carried by gvar's phantom points, HVAR dropped); the outlines shifted right by
    the nib's left extent, advances grown by its width, GPOS anchors moved along at
    every master (see the module docstring).

    ``src``: a path or ``TTFont``: a variable font (glyf/gvar or CFF2), or with
    ``nib_max`` a static one; ``nib``, ``nib_max``: (width, height, angle);
    ``glyphs``: glyph names (None: every glyph with contours; composites are
    decomposed); ``tol``: font units (fit FIT_SHARE, quadratics CU2QU_SHARE, a nib
    axis' blend BLEND_SHARE; the source's own masters' interpolation of the nib part
    is measured, not bounded: a source's masters are not a nib scale); ``split``:
    intermediate source masters, the master grid refined 2**split times per axis
    (:func:`source_locations`; Source Serif 4 with split 1: 25 masters instead of
    9); ``grade``: two growing disks make a GRAD axis (:func:`grade_axis`).
    Returns a dict: ``masters`` (normalized locations of the fitted masters),
    ``source_masters``, ``nib_values``, ``axis`` (:class:`NibAxis` or None),
    ``glyphs``, ``fit_seconds``, ``font``.

    Raises:
        ParseError: an unreadable font; MorphError: a static font without a nib axis,
            an outline format other than glyf or CFF/CFF2, a bad output suffix;
            ValueError: equal nibs.
    """
    from fontTools.varLib.models import VariationModel

    from .jobs import run_jobs
    from .tables import rename_family, save_font

    if str(out_path).lower().endswith(".otf"):
        raise MorphError("a variable brushed font is TrueType (glyf/gvar: the overlapping "
                         "contours are converted to quadratics compatibly): write .ttf, "
                         ".woff2 or .woff, not .otf")
    font = _open(src)
    kind = _outline_kind(font, src, nib_max)
    plan = _plan(font, nib, nib_max, tol, split, grade)
    sets = [font.getGlyphSet(location=loc, normalized=True) if loc else font.getGlyphSet()
            for loc in plan.src_locs]
    order = font.getGlyphOrder()
    chosen = _chosen(font, kind, glyphs, order)
    convert = [n for n in order if kind == "cff" and n not in chosen]
    brush = set(chosen)
    # made as the workers need them (run_jobs consumes a generator lazily)
    work = ((n, [_region_loops(gs, n) for gs in sets], plan.nibs if n in brush else None,
             plan.owners, FIT_SHARE * tol, CU2QU_SHARE * tol) for n in chosen + convert)
    report = None if progress is None else (lambda k, r: progress(r[0]))
    results = run_jobs(_brush_glyph_job, work, jobs=jobs, progress=report)
    written = [n for n, contours, _ in results if contours is not None]
    widths = [{n: gs[n].width for n in (order if kind == "cff" else written)} for gs in sets]
    if kind == "cff":
        _truetype_tables(font)
    if plan.axis is not None:
        _add_nib_axis(font, plan.axis, plan.values)
    shifts = _write_glyphs(font, plan, results, brush, widths)
    if kind == "cff":
        model = VariationModel(plan.locs, plan.tags)
        for name in set(order) - set(written):
            _write_empty(font, model, widths, plan.owners, name)
    for t in ("HVAR", "VVAR"):
        if t in font:
            del font[t]
    _move_anchors(font, shifts, plan.axis, plan.values, plan.tags)
    if family_name:
        rename_family(font, family_name)
    set_overlap_flags(font)
    save_font(font, out_path)
    return {"masters": plan.locs, "source_masters": plan.src_locs, "nib_values": plan.values,
            "axis": plan.axis, "glyphs": len(shifts),
            "fit_seconds": sum(r[2] for r in results), "font": font}


def _outline_kind(font, src, nib_max):
    """"glyf" or "cff" (CFF or CFF2) for a font a variable brush can read.

    Raises:
        MorphError: other outlines, a static font without a nib axis, fvar without
            gvar."""
    kind = "glyf" if "glyf" in font else ("cff" if ("CFF2" in font or "CFF " in font)
                                          else None)
    if kind is None:
        raise MorphError("%s has neither glyf nor CFF outlines" % (src,))
    if "fvar" not in font and nib_max is None:
        raise MorphError("%s is a static font: a variable brush needs a nib axis "
                         "(--vary-nib)" % (src,))
    if kind == "glyf" and "fvar" in font and "gvar" not in font:
        raise MorphError("%s has fvar but no gvar" % (src,))
    return kind


@dataclass
class _Plan:
    """The fitted masters of a variable brush: the nib ``axis`` (or None) and its
    master ``values``, the source masters' normalized locations ``src_locs``, per
    fitted master its source master (``owners``), nib (``nibs``) and normalized
    location over ``tags`` (``locs``)."""

    axis: object
    values: list
    src_locs: list
    owners: list
    nibs: list
    tags: list
    locs: list


def _plan(font, nib, nib_max, tol, split, grade):
    nib = Ellipse(*map(float, nib))
    axis = None
    if nib_max is not None:
        upm = font["head"].unitsPerEm
        axis = (grade and grade_axis(nib, nib_max, upm)) or nib_axis(nib, nib_max)
    values = [None] if axis is None else axis_masters(axis, BLEND_SHARE * tol)
    nibs_v = [nib] if axis is None else [axis.nib_at(v) for v in values]
    src_locs = source_locations(font, split)
    src_tags = [a.axisTag for a in font["fvar"].axes] if "fvar" in font else []
    fitted = [(s, k) for k in range(len(values)) for s in range(len(src_locs))]
    locs = [{**src_locs[s], **({axis.tag: axis.fraction(values[k])} if axis else {})}
            for s, k in fitted]
    return _Plan(axis, values, src_locs, [s for s, _ in fitted],
                 [nibs_v[k] for _, k in fitted], src_tags + ([axis.tag] if axis else []),
                 locs)


def _write_glyphs(font, plan, results, brushed, widths):
    """Every glyph of ``results`` written at every fitted master (brushed ones shifted
    by their nib, converted CFF glyphs as they are); returns the brushed glyphs'
    default shifts."""
    from fontTools.varLib.models import VariationModel

    model = VariationModel(plan.locs, plan.tags)
    shifts = {}
    for name, contours, _ in results:
        if contours is None:
            continue
        width0 = font["hmtx"][name][0]
        if name in brushed:
            shifts[name] = _write_glyph(font, model, widths, plan.owners, plan.nibs, name,
                                        contours, width0, plan.axis)
        else:                                       # a CFF glyph converted, not brushed
            _write_glyph(font, model, widths, plan.owners, None, name, contours, width0,
                         None)
    return shifts


def _chosen(font, kind, glyphs, order):
    """The glyphs brushed: ``glyphs`` (None: every glyph drawn by contours or
    components)."""
    if kind == "glyf":
        glyf = font["glyf"]
        return [n for n in order if (glyphs is None or n in glyphs)
                and glyf[n].numberOfContours != 0]
    return [n for n in order if glyphs is None or n in glyphs]


def _shift(nib, width0, axis):
    """(x shift of the outlines, advance growth) for a nib: right by the nib's left
    extent, advances grown by its width; a zero-width mark shifts left by the width
    and keeps advance 0.  A grade axis uses its default nib's at every master."""
    if axis is not None and axis.tag == "GRAD":
        nib = axis.nib_min
    hx = float(nib.extent()[2])
    grow = int(round(2 * hx))
    return hx - (grow if width0 == 0 else 0), (grow if width0 else 0)


def _write_glyph(font, model, widths, owners, nibs, name, contours, width0, axis):
    """Glyph ``name``'s quadratic contours of every fitted master written into the
    glyf (default master), hmtx and gvar (the other masters' deltas by ``model``,
    advances through the phantom points) of ``font``, shifted as :func:`_shift` says
    (``nibs`` None: not brushed, not shifted).  Returns the default master's shift
    (x, y) for the anchors."""
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    glyf, gvar, hmtx = font["glyf"], font["gvar"], font["hmtx"]
    coords = []
    for m, per in enumerate(contours):
        shift, grow = (0.0, 0) if nibs is None else _shift(nibs[m], width0, axis)
        pen = TTGlyphPen(None)
        for splines in per:
            pen.moveTo(_rnd(splines[0][0], shift))
            for s in splines:
                pen.qCurveTo(*[_rnd(p, shift) for p in s[1:]])
            pen.closePath()
        g = pen.glyph(dropImpliedOnCurves=False)
        adv = widths[owners[m]][name] + grow
        pts = list(g.coordinates) + [(0, 0), (int(round(adv)), 0), (0, 0), (0, 0)]
        coords.append(np.array(pts, float))
        if m == 0:
            glyph0, adv0, shift0 = g, adv, shift
    glyf[name] = glyph0
    glyph0.recalcBounds(glyf)
    hmtx[name] = (int(round(adv0)), glyph0.xMin)
    _set_variations(gvar, model, name, coords)
    return (shift0, 0.0)


def _write_empty(font, model, widths, owners, name):
    """A glyph without contours (a space) of a converted CFF font: its advance at
    every master."""
    from fontTools.ttLib.tables._g_l_y_f import Glyph

    font["glyf"][name] = Glyph()
    coords = [np.array([(0, 0), (int(round(widths[o][name])), 0), (0, 0), (0, 0)], float)
              for o in owners]
    font["hmtx"][name] = (int(round(coords[0][1][0])), 0)
    _set_variations(font["gvar"], model, name, coords)


def _set_variations(gvar, model, name, coords):
    from fontTools.ttLib.tables.TupleVariation import TupleVariation

    deltas, supports = model.getDeltas(coords), model.supports
    gvar.variations[name] = [TupleVariation(sup, [tuple(map(int, np.round(p))) for p in d])
                             for d, sup in zip(deltas[1:], supports[1:])
                             if np.any(np.round(d) != 0)]


def _rnd(p, shift):
    return (int(round(p[0] + shift)), int(round(p[1])))


# ------------------------------------------------------------------- tables

def _truetype_tables(font):
    """Make a CFF / CFF2 font TrueType: the outline table replaced by empty glyf /
    loca and gvar (every glyph is written after), maxp 1.0, head's glyph data format
    0, post format 2 (the glyph names kept)."""
    from fontTools.ttLib import newTable
    from fontTools.ttLib.tables._g_l_y_f import Glyph

    order = font.getGlyphOrder()
    for tag in ("CFF ", "CFF2", "VORG"):
        if tag in font:
            del font[tag]
    glyf = font["glyf"] = newTable("glyf")
    glyf.glyphOrder = order
    glyf.glyphs = {}
    glyf.glyphs.update({n: Glyph() for n in order})
    font["loca"] = newTable("loca")
    gvar = font["gvar"] = newTable("gvar")
    gvar.version, gvar.reserved, gvar.variations = 1, 0, {}
    maxp = font["maxp"]
    maxp.tableVersion = 0x00010000
    for k in ("maxZones", "maxTwilightPoints", "maxStorage", "maxFunctionDefs",
              "maxInstructionDefs", "maxStackElements", "maxSizeOfInstructions",
              "maxComponentElements", "maxPoints", "maxContours", "maxCompositePoints",
              "maxCompositeContours", "maxComponentDepth"):
        setattr(maxp, k, 1 if k == "maxZones" else 0)
    font["head"].glyphDataFormat = 0
    post = font["post"]
    post.formatType = 2.0
    post.extraNames, post.mapping = [], {}
    font.sfntVersion = "\x00\x01\x00\x00"


def _name_id(font, text):
    return font["name"].addMultilingualName({"en": text}, ttFont=font, mac=False)


def _add_nib_axis(font, axis, values):
    """fvar (new for a static source), avar, STAT, gvar and every item variation
    store of ``font`` given the nib axis (appended after the source's axes)."""
    from fontTools.ttLib import newTable
    from fontTools.ttLib.tables._f_v_a_r import Axis, NamedInstance

    static = "fvar" not in font
    if static:
        fvar = font["fvar"] = newTable("fvar")
        fvar.axes, fvar.instances = [], []
    fvar = font["fvar"]
    ax = Axis()
    ax.axisTag, ax.axisNameID = axis.tag, _name_id(font, axis.name)
    ax.minValue, ax.defaultValue, ax.maxValue = axis.minimum, axis.minimum, axis.maximum
    ax.flags = 0
    fvar.axes.append(ax)
    for inst in fvar.instances:
        inst.coordinates[axis.tag] = axis.minimum
    if static:
        for v in (axis.minimum, axis.value(0.5), axis.maximum):
            inst = NamedInstance()
            style = "Regular" if v == axis.minimum else "%s %g" % (axis.name.split()[0],
                                                                  round(v, 2))
            inst.subfamilyNameID = 2 if v == axis.minimum else _name_id(font, style)
            inst.postscriptNameID = 0xFFFF
            inst.coordinates = {axis.tag: v}
            inst.flags = 0
            fvar.instances.append(inst)
    if "avar" in font:
        font["avar"].segments[axis.tag] = {-1.0: -1.0, 0.0: 0.0, 1.0: 1.0}
    if "gvar" not in font:
        gvar = font["gvar"] = newTable("gvar")
        gvar.version, gvar.reserved, gvar.variations = 1, 0, {}
    for store in _var_stores(font):
        _widen_regions(store, len(fvar.axes))
    _add_stat(font, axis, values)


def _var_stores(font):
    """The item variation stores of ``font`` that hold regions over fvar's axes."""
    for tag in ("GDEF", "MVAR", "BASE", "COLR"):
        if tag in font:
            store = getattr(font[tag].table, "VarStore", None)
            if store is not None:
                yield store


def _widen_regions(store, axis_count):
    """Every region of ``store`` given the appended axes as not involved (start,
    peak, end 0)."""
    from fontTools.ttLib.tables import otTables as ot

    regions = store.VarRegionList
    for region in regions.Region:
        while len(region.VarRegionAxis) < axis_count:
            r = ot.VarRegionAxis()
            r.StartCoord = r.PeakCoord = r.EndCoord = 0.0
            region.VarRegionAxis.append(r)
    regions.RegionAxisCount = axis_count


def _add_stat(font, axis, values):
    """STAT gets the nib axis (its default elidable "Regular", the middle and the
    maximum named); a font without STAT gets one for all its axes."""
    from fontTools.otlLib.builder import buildStatTable

    labels = [{"value": axis.minimum, "name": "Regular", "flags": 0x2},
              {"value": axis.value(0.5), "name": "%s %g" % (axis.name.split()[0],
                                                           round(axis.value(0.5), 2))},
              {"value": axis.maximum, "name": "%s %g" % (axis.name.split()[0],
                                                        round(axis.maximum, 2))}]
    if "STAT" not in font:
        axes = [{"tag": a.axisTag, "name": font["name"].getDebugName(a.axisNameID) or a.axisTag,
                 "values": labels if a.axisTag == axis.tag else
                 [{"value": a.defaultValue, "name": "Regular", "flags": 0x2}]}
                for a in font["fvar"].axes]
        buildStatTable(font, axes, elidedFallbackName=2)
        return
    from fontTools.ttLib.tables import otTables as ot

    stat = font["STAT"].table
    rec = ot.AxisRecord()
    rec.AxisTag, rec.AxisNameID = axis.tag, font["fvar"].axes[-1].axisNameID
    if stat.DesignAxisRecord is None:
        stat.DesignAxisRecord = ot.AxisRecordArray()
        stat.DesignAxisRecord.Axis = []
    rec.AxisOrdering = len(stat.DesignAxisRecord.Axis)
    stat.DesignAxisRecord.Axis.append(rec)
    stat.DesignAxisCount = len(stat.DesignAxisRecord.Axis)
    if stat.AxisValueArray is None:
        stat.AxisValueArray = ot.AxisValueArray()
        stat.AxisValueArray.AxisValue = []
    for lab in labels:
        av = ot.AxisValue()
        av.Format, av.AxisIndex, av.Flags = 1, rec.AxisOrdering, lab.get("flags", 0)
        av.ValueNameID = 2 if lab["name"] == "Regular" and not stat.ElidedFallbackNameID \
            else _name_id(font, lab["name"])
        av.Value = lab["value"]
        stat.AxisValueArray.AxisValue.append(av)
    stat.AxisValueCount = len(stat.AxisValueArray.AxisValue)


# ------------------------------------------------------------------ anchors

def _move_anchors(font, shifts, axis, values, tags):
    """GPOS anchors and GDEF carets moved by the default master's shifts, and where
    the shift varies along the nib axis given the variation (see the module
    docstring)."""
    from .tables import move_anchors

    if axis is not None and axis.tag != "GRAD":
        per_master = {}
        for name, (s0, _) in shifts.items():
            width0 = font["hmtx"][name][0]
            per = [_shift(axis.nib_at(v), width0, axis)[0] for v in values]
            if any(abs(x - s0) > 1e-9 for x in per):
                per_master[name] = per
        if per_master:
            _vary_anchors(font, per_master, axis, values, tags)
    move_anchors(font, shifts)


def _anchor_slots(font):
    """(glyph, record, attribute) of every anchor move_anchors moves."""
    from .tables import _lookup_subtables

    def records(glyphs, recs, attrs):
        for g, rec in zip(glyphs, recs):
            for attr in attrs:
                yield g, rec, attr

    for st in _lookup_subtables(font):
        kind = type(st).__name__
        if kind in ("MarkBasePos", "MarkLigPos"):
            yield from records(st.MarkCoverage.glyphs, st.MarkArray.MarkRecord, ("MarkAnchor",))
        if kind == "MarkBasePos":
            yield from records(st.BaseCoverage.glyphs, st.BaseArray.BaseRecord, ("BaseAnchor",))
        elif kind == "MarkMarkPos":
            yield from records(st.Mark1Coverage.glyphs, st.Mark1Array.MarkRecord,
                               ("MarkAnchor",))
            yield from records(st.Mark2Coverage.glyphs, st.Mark2Array.Mark2Record,
                               ("Mark2Anchor",))
        elif kind == "MarkLigPos":
            for g, att in zip(st.LigatureCoverage.glyphs, st.LigatureArray.LigatureAttach):
                yield from records([g] * len(att.ComponentRecord), att.ComponentRecord,
                                   ("LigatureAnchor",))
        elif kind == "CursivePos":
            yield from records(st.Coverage.glyphs, st.EntryExitRecord,
                               ("EntryAnchor", "ExitAnchor"))


def _vary_anchors(font, shifts, axis, values, tags):
    """Anchors of the glyphs in ``shifts`` (their x shift at every nib master) given
    an x variation along the nib axis, before they move by the default's shift: the
    anchor at x goes to round(x + shift) at every nib master; format 3 anchors whose
    XDeviceTable indexes a row of GDEF's item variation store with the deltas of
    those (a 1-D model over the nib masters) and, for an anchor that varied already,
    its own deltas of the source's regions copied into the same row."""
    from fontTools.varLib.builder import (buildVarData, buildVarDevTable, buildVarRegion,
                                          buildVarRegionList, buildVarStore)
    from fontTools.varLib.models import VariationModel
    from fontTools.ttLib import newTable
    from fontTools.ttLib.tables import otTables as ot

    model = VariationModel([{axis.tag: axis.fraction(v)} for v in values], [axis.tag])
    if "GDEF" not in font:
        gdef = font["GDEF"] = newTable("GDEF")
        gdef.table = ot.GDEF()
        gdef.table.Version = 0x00010003
        for attr in ("GlyphClassDef", "AttachList", "LigCaretList", "MarkAttachClassDef",
                     "MarkGlyphSetsDef"):
            setattr(gdef.table, attr, None)
    gdef = font["GDEF"].table
    if getattr(gdef, "VarStore", None) is None:
        gdef.Version = 0x00010003
        for attr in ("MarkGlyphSetsDef",):
            if not hasattr(gdef, attr):
                setattr(gdef, attr, None)
        gdef.VarStore = buildVarStore(buildVarRegionList([], tags), [])
    store = gdef.VarStore
    first = len(store.VarRegionList.Region)
    nib_regions = []
    for sup in model.supports[1:]:
        store.VarRegionList.Region.append(buildVarRegion(sup, tags))
        nib_regions.append(first + len(nib_regions))
    store.VarRegionList.RegionCount = len(store.VarRegionList.Region)
    rows = {}                   # (old var index or None, nib deltas) -> new var index
    datas = {}                  # old outer index or None -> (VarData index, rows list)
    for g, rec, attr in list(_anchor_slots(font)):
        if g not in shifts:
            continue
        anchors = getattr(rec, attr)
        many = isinstance(anchors, list)
        new = []
        for a in (anchors if many else [anchors]):
            if a is None:
                new.append(None)
                continue
            at = [round(a.XCoordinate + x) for x in shifts[g]]
            d = [int(round(x)) for x in model.getDeltas([x - at[0] for x in at])[1:]]
            old = None
            if a.Format == 3 and a.XDeviceTable is not None and \
                    a.XDeviceTable.DeltaFormat == 0x8000:
                old = (a.XDeviceTable.StartSize, a.XDeviceTable.EndSize)
            key = (old, tuple(d))
            if key not in rows:
                rows[key] = _add_row(store, datas, old, d, nib_regions, buildVarData)
            b = ot.Anchor()
            b.Format, b.XCoordinate, b.YCoordinate = 3, a.XCoordinate, a.YCoordinate
            b.XDeviceTable = buildVarDevTable(rows[key])
            b.YDeviceTable = a.YDeviceTable if a.Format == 3 else None
            new.append(b)
        setattr(rec, attr, new if many else new[0])
    store.VarDataCount = len(store.VarData)


def _add_row(store, datas, old, deltas, nib_regions, build):
    """A new row of ``store``: the nib deltas, after the old row's deltas (``old``:
    (outer, inner) of the anchor's variation, or None); returns its var index."""
    outer = None if old is None else old[0]
    if outer not in datas:
        regions = (list(store.VarData[outer].VarRegionIndex) if outer is not None else []) + \
            nib_regions
        data = build(regions, [], optimize=False)
        store.VarData.append(data)
        datas[outer] = len(store.VarData) - 1
    k = datas[outer]
    data = store.VarData[k]
    row = (list(store.VarData[outer].Item[old[1]]) if old is not None else []) + list(deltas)
    data.Item.append(row)
    data.ItemCount = len(data.Item)
    return (k << 16) + len(data.Item) - 1

"""Variable brushed fonts: a compiled font's glyphs ⊕ elliptical nibs as a variable
font, with the source's axes (a variable source) and an optional nib axis.

Every master of the source, and intermediate ones where the source's interpolation
and the nib do not commute (:mod:`morph.fonts.variable_sources`: added glyph by
glyph until the glyph's blend is within its share of tol; each glyph has its own
masters, the sparse masters of a designspace), is brushed by every nib master, as
untrimmed overlapping contours fitted with common breaks across all of them
(:func:`morph.compatible.region_elements`).  Written into a copy of the source,
each glyph's variations computed by fontTools' ``VariationModel`` over its own
masters' locations (:func:`morph.fonts.variable_grid.grid_model`'s tents):

- TrueType (``.ttf``, ``.woff2``, ``.woff``): the cubics converted to quadratics
  compatibly (cu2qu on all masters' curves at once) into glyf/gvar, the advances
  by gvar's phantom points, the overlap flags set;
- CFF2 (``.otf``): the cubics as fitted, in blended charstrings, the advances by
  HVAR (:mod:`morph.fonts.variable_cff2`); CFF2 fills nonzero, no flag needed.

The error budget is that of :mod:`morph.fonts.variable`.

Sources:

- a variable TrueType font (glyf/gvar): its axes, avar, STAT, named instances and
  layout are kept; its grid of masters holds every region's start, peak and end;
- a variable CFF2 font: read through fontTools' glyph set at each master location
  (its variation regions' coordinates); for TrueType output the CFF2 table is
  replaced by glyf/loca/gvar (every glyph converted compatibly, the ones not
  brushed too), maxp/head/post made TrueType's;
- a static font (.ttf or .otf) with a nib axis: fvar, STAT and gvar or CFF2's
  variation store are added.

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

from ..compatible import Ellipse, fit_elements, interpolation_error, region_elements
from ..errors import MorphError, ParseError
from .variable import BLEND_SHARE, CU2QU_SHARE, FIT_SHARE, NibAxis, axis_masters, nib_axis, \
    set_overlap_flags
from .variable_sources import counter_clockwise, refine_sources, region_loops

__all__ = ["brush_variable", "grade_axis"]


def grade_axis(nib_min, nib_max, upm):
    """The GRAD :class:`NibAxis` between two disks (the second larger): user value the
    growth of the diameter in units per 1000 em; None when the nibs are not two
    growing disks."""
    a, b = Ellipse(*map(float, nib_min)), Ellipse(*map(float, nib_max))
    if a.width != a.height or b.width != b.height or not b.width > a.width:
        return None
    grow = (b.width - a.width) * 1000.0 / upm
    return NibAxis("GRAD", "Grade", 0.0, round(grow, 3), a, b)


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
    """(name, per fitted master contours or None, CPU s) of one glyph: its loops at
    every source master ⊕ the nib of every fitted master (``nibs``, the source
    master of each: ``owners``), or with ``nibs`` None the glyph itself at every
    fitted master (a glyph converted, not brushed).  Contours: quadratic splines
    (cu2qu within ``q_tol``), or with ``q_tol`` None cubics ((k, 4, 2) arrays)."""
    name, loops_by_source, nibs, owners, fit_tol, q_tol = args
    t0 = time.process_time()
    if not loops_by_source[0]:
        return name, None, 0.0
    loops_by_source = counter_clockwise(loops_by_source)
    if nibs is None:
        fits = [[np.array([_cubic(p) for p in loop]) for loop in loops_by_source[o]]
                for o in owners]
    else:
        fits = fit_elements(region_elements(loops_by_source, "glyph %r" % name), nibs, owners,
                            fit_tol)
    out = fits if q_tol is None else _to_quadratic(fits, q_tol)
    return name, out, time.process_time() - t0


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
                   progress=None, refine=True, nib_max=None, grade=True):
    """Brush a font into a variable font: every master of every chosen glyph ⊕ the
    nib (with ``nib_max`` every nib master of the nib axis) as untrimmed overlapping
    contours fitted compatibly across the masters, written into a copy of the source
    (its layout, names, STAT and avar kept): ``.ttf`` / ``.woff2`` / ``.woff``
    glyf/gvar (quadratics by cu2qu on all masters at once, advances by gvar's
    phantom points), ``.otf`` CFF2 (cubics as fitted, advances by HVAR); outlines
    shifted right by the nib's left extent, advances grown by its width, GPOS
    anchors moved along at every master (see the module docstring).

    ``src``: a path or ``TTFont``, variable (glyf/gvar or CFF2) or, with ``nib_max``,
    static; ``nib``, ``nib_max``: (width, height, angle); ``glyphs``: names (None:
    every glyph with contours; composites decomposed); ``tol``: font units, FIT_SHARE
    fit, CU2QU_SHARE quadratics, BLEND_SHARE an instance's blend (halved between the
    nib axis and the source's axes when both are inexact); ``refine``: intermediate
    source masters until the blend holds (:func:`refine_sources`; False: the
    source's grid only); ``grade``: two growing disks make GRAD (:func:`grade_axis`).
    Returns a dict: ``masters`` (normalized locations of every fitted master of
    the font), ``source_masters``, ``glyph_masters`` (per written glyph, its own
    fitted masters' count), ``nib_values``, ``axis``, ``refinement``
    (refine_sources' report or None), ``glyphs``, ``fit_seconds``, ``font``.

    Raises:
        ParseError: an unreadable font; MorphError: a static font without a nib axis,
            outlines other than glyf or CFF/CFF2, a bad suffix, too many masters;
            ValueError: equal nibs.
    """
    cff2 = _output_format(out_path) == "cff2"
    font = _open(src)
    kind = _outline_kind(font, src, nib_max)
    order = font.getGlyphOrder()
    chosen = _chosen(font, kind, glyphs, order)
    plan = _plan(font, nib, nib_max, tol, refine, grade, chosen)
    every = kind == "cff" or cff2           # every glyph's outlines written anew
    convert = [n for n in order if n not in set(chosen)] if every else []
    sets = _GlyphSets(font, plan.src_locs)
    results = _brush_glyphs(sets, plan, chosen, convert, tol, jobs, progress, cff2)
    widths = sets.width
    write = _write_cff2 if cff2 else _write_truetype
    shifts = write(font, kind, plan, results, set(chosen), widths)
    _move_anchors(font, shifts, plan.axis, plan.values, plan.tags)
    if family_name:
        from .tables import rename_family

        rename_family(font, family_name)
    _save(font, out_path, cff2)
    return {"masters": plan.all_masters(), "source_masters": plan.src_locs,
            "glyph_masters": {n: len(plan.masters(n).locs) for n in shifts},
            "nib_values": plan.values, "axis": plan.axis, "refinement": plan.report,
            "glyphs": len(shifts), "fit_seconds": sum(r[2] for r in results), "font": font}


class _GlyphSets:
    """The source's glyph sets at the plan's source master locations, made as they are
    first asked for (a glyph reads only its own masters)."""

    def __init__(self, font, locations):
        self.font, self.locations, self.sets = font, locations, {}

    def __getitem__(self, s):
        if s not in self.sets:
            loc = self.locations[s]
            self.sets[s] = self.font.getGlyphSet(location=loc, normalized=True) if loc \
                else self.font.getGlyphSet()
        return self.sets[s]

    def width(self, s, name):
        """The advance of glyph ``name`` at source master ``s``."""
        return self[s][name].width


def _output_format(out_path):
    """"truetype" (.ttf, .woff2, .woff) or "cff2" (.otf) for a variable brushed font.

    Raises:
        MorphError: another suffix."""
    suffix = str(out_path).lower().rsplit(".", 1)[-1]
    if suffix == "otf":
        return "cff2"
    if suffix in ("ttf", "woff2", "woff"):
        return "truetype"
    raise MorphError("a variable brushed font is .ttf, .woff2, .woff (glyf/gvar) or .otf "
                     "(CFF2), got %s" % out_path)


def _brush_glyphs(sets, plan, chosen, convert, tol, jobs, progress, cff2):
    """run_jobs of :func:`_brush_glyph_job` over the glyphs brushed (``chosen``) and
    converted (``convert``): each glyph's loops read from its own source masters'
    glyph ``sets`` (:class:`_GlyphSets`) as the workers need them (run_jobs consumes
    the generator lazily)."""
    from .jobs import run_jobs

    brush = set(chosen)
    q_tol = None if cff2 else CU2QU_SHARE * tol
    def job(n):
        m = plan.masters(n)
        return (n, [region_loops(sets[s], n) for s in m.sources],
                m.nibs if n in brush else None, m.owners, FIT_SHARE * tol, q_tol)

    work = (job(n) for n in chosen + convert)
    report = None if progress is None else (lambda k, r: progress(r[0]))
    return run_jobs(_brush_glyph_job, work, jobs=jobs, progress=report)


def _write_truetype(font, kind, plan, results, brushed, widths):
    """The results written as glyf/gvar into ``font`` (a CFF source made TrueType
    first; its glyphs without contours get their advances at every master); the nib
    axis added; HVAR / VVAR dropped (gvar's phantom points carry the advances).
    Returns the brushed glyphs' default shifts."""
    if kind == "cff":
        _truetype_tables(font)
    if plan.axis is not None:
        _add_nib_axis(font, plan.axis, plan.values)
    shifts = _write_glyphs(font, plan, results, brushed, widths)
    if kind == "cff":
        written = {n for n, contours, _ in results if contours is not None}
        for name in set(font.getGlyphOrder()) - written:
            _write_empty(font, plan.masters(name), widths, name)
    for t in ("HVAR", "VVAR"):
        if t in font:
            del font[t]
    set_overlap_flags(font)
    return shifts


def _write_cff2(font, kind, plan, results, brushed, widths):
    """The results written as a CFF2 table with HVAR (:mod:`morph.fonts.variable_cff2`),
    the nib axis added.  Returns the brushed glyphs' default shifts."""
    from .variable_cff2 import write_cff2

    if plan.axis is not None:
        _add_nib_axis(font, plan.axis, plan.values)
    moved = {}
    for name, contours, _ in results:
        if contours is not None and name in brushed:
            width0 = int(round(widths(0, name)))
            moved[name] = [_shift(n, width0, plan.axis) for n in plan.masters(name).nibs]
    return write_cff2(font, plan, results, moved, widths)


def _save(font, out_path, cff2):
    from .tables import save_font

    if cff2:
        font.sfntVersion = "OTTO"
    save_font(font, out_path)


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
    """The fitted masters of a variable brush: the nib ``axis`` (or None), its master
    ``values`` and their nibs ``nibs_v``, the source masters' normalized locations
    ``src_locs`` (every glyph's, the source's grid first: ``given`` of them), each
    glyph's own source masters (``per_glyph``: indices into ``src_locs``; a glyph not
    in it, one converted and not brushed, has the source's grid) and the
    refinement's ``report``.  :meth:`masters` gives a glyph's fitted masters."""

    axis: object
    values: list
    nibs_v: list
    src_locs: list
    given: int
    per_glyph: dict
    tags: list
    report: dict = None

    def __post_init__(self):
        self._masters = {}

    def sources(self, name):
        return self.per_glyph.get(name) or list(range(self.given))

    def masters(self, name):
        """The fitted masters of glyph ``name`` (:class:`_Masters`; the same object
        for glyphs with the same source masters)."""
        key = tuple(self.sources(name))
        if key not in self._masters:
            fitted = [(j, k) for k in range(len(self.values)) for j in range(len(key))]
            locs = [{**self.src_locs[key[j]],
                     **({self.axis.tag: self.axis.fraction(self.values[k])} if self.axis
                        else {})} for j, k in fitted]
            self._masters[key] = _Masters(list(key), [j for j, _ in fitted],
                                          [self.nibs_v[k] for _, k in fitted], locs,
                                          _grid_model(locs, self.tags))
        return self._masters[key]

    def all_masters(self):
        """Every fitted location of the font (every source master at every nib
        master)."""
        return [{**loc, **({self.axis.tag: self.axis.fraction(v)} if self.axis else {})}
                for v in self.values for loc in self.src_locs]


@dataclass
class _Masters:
    """One glyph's fitted masters: its source masters (``sources``, indices into the
    plan's ``src_locs``), per fitted master the position of its source master among
    them (``owners``), its nib (``nibs``) and normalized location (``locs``), and
    the variation ``model`` over them (:func:`morph.fonts.variable_grid.grid_model`)."""

    sources: list
    owners: list
    nibs: list
    locs: list
    model: object

    def source(self, m):
        """The plan's source master of fitted master ``m``."""
        return self.sources[self.owners[m]]


def _grid_model(locs, tags):
    from .variable_grid import grid_model

    return grid_model(locs, tags)


def _plan(font, nib, nib_max, tol, refine, grade, chosen):
    """The :class:`_Plan`: nib masters within their share of the blend budget
    (:func:`axis_masters`), each brushed glyph's source masters within theirs
    (:func:`refine_sources`, with every nib master); each gets half of BLEND_SHARE
    when both the nib axis and a variable source's axes are inexact."""
    nib = Ellipse(*map(float, nib))
    axis = None
    if nib_max is not None:
        upm = font["head"].unitsPerEm
        axis = (grade and grade_axis(nib, nib_max, upm)) or nib_axis(nib, nib_max)
    both = axis is not None and "fvar" in font and \
        interpolation_error(axis.nib_min, axis.nib_max) > 1e-9 * axis.nib_max.width
    share = BLEND_SHARE * tol / (2.0 if both else 1.0)
    values = [None] if axis is None else axis_masters(axis, share)
    nibs_v = [nib] if axis is None else [axis.nib_at(v) for v in values]
    src_locs, per_glyph, report = refine_sources(font, chosen, nibs_v, share, refine)
    src_tags = [a.axisTag for a in font["fvar"].axes] if "fvar" in font else []
    given = 1 if report is None else report["given"]
    return _Plan(axis, values, nibs_v, src_locs, given, per_glyph,
                 src_tags + ([axis.tag] if axis else []), report)


def _write_glyphs(font, plan, results, brushed, widths):
    """Every glyph of ``results`` written at every fitted master (brushed ones shifted
    by their nib, converted CFF glyphs as they are); returns the brushed glyphs'
    default shifts."""
    shifts = {}
    for name, contours, _ in results:
        if contours is None:
            continue
        width0 = font["hmtx"][name][0]
        if name in brushed:
            shifts[name] = _write_glyph(font, plan.masters(name), widths, True, name,
                                        contours, width0, plan.axis)
        else:                                       # a CFF glyph converted, not brushed
            _write_glyph(font, plan.masters(name), widths, False, name, contours, width0,
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


def _write_glyph(font, masters, widths, brushed, name, contours, width0, axis):
    """Glyph ``name``'s quadratic contours of each of its fitted ``masters``
    (:class:`_Masters`) written into the glyf (default master), hmtx and gvar (the
    other masters' deltas by the glyph's own model, its regions those of its own
    masters; advances through the phantom points) of ``font``, shifted as
    :func:`_shift` says (``brushed`` False: not shifted).  Returns the default master's shift
    (x, y) for the anchors."""
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    glyf, gvar, hmtx = font["glyf"], font["gvar"], font["hmtx"]
    coords = []
    for m, per in enumerate(contours):
        shift, grow = (0.0, 0) if not brushed else _shift(masters.nibs[m], width0, axis)
        pen = TTGlyphPen(None)
        for splines in per:
            pen.moveTo(_rnd(splines[0][0], shift))
            for s in splines:
                pen.qCurveTo(*[_rnd(p, shift) for p in s[1:]])
            pen.closePath()
        g = pen.glyph(dropImpliedOnCurves=False)
        adv = widths(masters.source(m), name) + grow
        pts = list(g.coordinates) + [(0, 0), (int(round(adv)), 0), (0, 0), (0, 0)]
        coords.append(np.array(pts, float))
        if m == 0:
            glyph0, adv0, shift0 = g, adv, shift
    glyf[name] = glyph0
    glyph0.recalcBounds(glyf)
    hmtx[name] = (int(round(adv0)), glyph0.xMin)
    _set_variations(gvar, masters.model, name, coords)
    return (shift0, 0.0)


def _write_empty(font, masters, widths, name):
    """A glyph without contours (a space) of a converted CFF font: its advance at
    every master."""
    from fontTools.ttLib.tables._g_l_y_f import Glyph

    font["glyf"][name] = Glyph()
    coords = [np.array([(0, 0), (int(round(widths(masters.source(m), name))), 0), (0, 0),
                        (0, 0)], float) for m in range(len(masters.locs))]
    font["hmtx"][name] = (int(round(coords[0][1][0])), 0)
    _set_variations(font["gvar"], masters.model, name, coords)


def _set_variations(gvar, model, name, coords):
    from fontTools.ttLib.tables.TupleVariation import TupleVariation

    # integer masters on the grid model's tents: integer deltas, every master exactly
    # its own rounded outline (the rounding only drops the floats' noise)
    deltas = model.getDeltas(coords, round=np.round)
    gvar.variations[name] = [TupleVariation(sup, [tuple(map(int, p)) for p in d])
                             for d, sup in zip(deltas[1:], model.supports[1:])
                             if np.any(d != 0)]


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
    from fontTools.varLib.builder import buildVarData, buildVarDevTable, buildVarRegion
    from fontTools.varLib.models import VariationModel
    from fontTools.ttLib.tables import otTables as ot

    model = VariationModel([{axis.tag: axis.fraction(v)} for v in values], [axis.tag])
    store = _gdef_store(font, tags)
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
            d = [int(x) for x in model.getDeltas([x - at[0] for x in at], round=round)[1:]]
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


def _gdef_store(font, tags):
    """GDEF's item variation store (GDEF 1.3 made, or added, where there is none)."""
    from fontTools.varLib.builder import buildVarRegionList, buildVarStore
    from fontTools.ttLib import newTable
    from fontTools.ttLib.tables import otTables as ot

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
        if not hasattr(gdef, "MarkGlyphSetsDef"):
            gdef.MarkGlyphSetsDef = None
        gdef.VarStore = buildVarStore(buildVarRegionList([], tags), [])
    return gdef.VarStore


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

"""Variable calligraphic fonts: a nib axis, masters compatible by construction.

A skeleton UFO stroked by elliptical nibs at several axis positions gives master
UFOs whose outlines are the *untrimmed* convolutions of :mod:`morph.compatible`:
overlapping contours whose nonzero fill is exactly skeleton ⊕ nib (Guibas, Ramshaw,
Stolfi), fitted with the same breaks in every master, so the masters have the same
contours and points.  A designspace is written beside them (a designer can open and
edit both) and compiled with ufo2ft's variable compilers: ``.ttf`` glyf/gvar
(:func:`ufo2ft.compileVariableTTF`, cubics converted to quadratics compatibly by
cu2qu), ``.otf`` CFF2 (:func:`ufo2ft.compileVariableCFF2`).  Every glyph's
OVERLAP_SIMPLE flag (OVERLAP_COMPOUND for composites) is set, so that renderers fill
overlapping contours as one (CFF2 charstrings need none: they are filled nonzero).
Static outputs of ``morph stroke`` stay trimmed and free of overlaps.

The nib axis runs from the ``nib_min`` nib (its minimum, the default master) to the
``nib_max`` nib (its maximum); at a fraction u of the way the nib's width, height and
angle are each interpolated linearly (:func:`morph.compatible.blend_nib`).  Its tag:

- ``NIBW`` ("Nib width"), user values the nib's width in font units, when the width
  grows along the axis: a reader sets the pen width directly (CSS
  ``font-variation-settings: "NIBW" 80``).
- ``NIBP`` ("Nib position"), user values 0 to 100 (percent of the way), otherwise
  (an angle or height change at a fixed width).

Private (uppercase) tags, not ``wght``: the registered weight axis has the CSS
weight scale (100 to 900, usWeightClass) and keeps a glyph's proportions, while a
nib axis is measured in font units, widens the advances by the nib and changes the
stroke contrast with the nib's shape; nor ``GRAD``, which must keep the advances.

Error budget (``tol`` font units, before integer rounding), every share measured:

- :data:`FIT_SHARE` of tol: each master's nib part fitted by cubics
  (:func:`morph.compatible.fit_elements`, at the sample parameters);
- :data:`CU2QU_SHARE`: the TrueType quadratic conversion (ufo2ft's compatible
  cu2qu, ``cubicConversionError``);
- :data:`BLEND_SHARE`: an instance between two masters, against the sum with the
  nib the axis defines there (:func:`morph.compatible.interpolation_error` of the
  two masters' nibs); intermediate masters are added until it holds.  A uniform
  scale (same aspect and angle) needs none: the masters' cubics are c + s H and
  interpolate exactly.  A skeleton designspace's masters get intermediate ones too
  (:mod:`morph.fonts.variable_skeleton`: the nib does not follow the skeleton's
  interpolation); with an inexact nib axis as well, each gets half the share.

So every master and every instance is within tol of the exact sum before the
integer rounding of the compiled font (<= 0.71 unit for the masters' points and
again for an instance's).  The gvar deltas are not IUP-optimised (``optimizeGvar``
off): IUP's 0.5-unit tolerance would come on top of the bound.  The masters fill a
product grid (the skeleton's masters times the nib axis'), and the variation model's
supports are the grid's tents (:class:`morph.fonts.variable_grid.grid_supports`):
fontTools' own let a master between others weigh 1/2 or 1/3 at its neighbours, so
its rounded deltas reproduce a master only within 0.5 unit per coordinate, and in
CFF2's relative charstring coordinates that error runs on along the contour
(so the bound above would need a third rounding); with the tents every master is
exactly its own rounded outline.

A variable TrueType font brushed keeping its axes
(:func:`morph.fonts.variable_brush.brush_variable`) is the same construction on filled
glyphs (:func:`morph.compatible.region_elements`): every master of the source, and
intermediate ones on its master grid (the nib part of distant masters does not
interpolate), ⊕ the nib, fitted with common breaks, written into the glyf/gvar of a
copy of the source.

Metrics as in the static stroke (:mod:`morph.fonts.stroke`): each master's
outlines shift right by its nib's left extent and the advances grow by the nib's
width (rounded), zero-width marks keep advance 0 and shift left by the width;
anchors move with the outlines (the nib is centred: its centre adds nothing; the
explicit anchors of the default skeleton's feature file, the one ufo2ft compiles,
become variable anchors, :func:`morph.fonts.fea.vary_feature_anchors`, with each
master's own values where the masters' feature files differ; each master's UFO
kerning and glyph anchors are its own, compiled into variable GPOS by ufo2ft's
feature writers), kept
components are re-placed, scaled / turned components decomposed and stroked.
"""

import copy
import os
import shutil
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..compatible import Ellipse, blend_nib, fit_elements, interpolation_error, skeleton_elements
from ..errors import MorphError, ParseError, one_line

__all__ = ["NibAxis", "nib_axis", "axis_masters", "stroke_variable", "variable_outputs",
           "set_overlap_flags", "read_skeleton", "Skeleton", "FIT_SHARE", "CU2QU_SHARE",
           "BLEND_SHARE"]

FIT_SHARE = 0.4
CU2QU_SHARE = 0.2
BLEND_SHARE = 0.4

#: at most this many masters on the nib axis (a bound on how far intermediate
#: masters are added: an angle change of a thin nib needs many)
MAX_MASTERS = 65

OVERLAP_KEY = "public.truetype.overlap"


@dataclass(frozen=True)
class NibAxis:
    """A nib axis from ``nib_min`` (user value ``minimum``) to ``nib_max``
    (``maximum``), user values linear in the fraction u of the way."""

    tag: str
    name: str
    minimum: float
    maximum: float
    nib_min: Ellipse
    nib_max: Ellipse

    def fraction(self, value):
        return (float(value) - self.minimum) / (self.maximum - self.minimum)

    def value(self, u):
        return self.minimum + float(u) * (self.maximum - self.minimum)

    def nib_at(self, value):
        """The nib at user value ``value`` (width, height, angle interpolated)."""
        return blend_nib(self.nib_min, self.nib_max, self.fraction(value))


def nib_axis(nib_min, nib_max):
    """The :class:`NibAxis` from ``nib_min`` to ``nib_max`` ((width, height, angle)
    each); see the module docstring for the choice of tag.

    Raises:
        ValueError: the two nibs are the same.
    """
    a, b = Ellipse(*map(float, nib_min)), Ellipse(*map(float, nib_max))
    if a == b:
        raise ValueError("the nib axis needs two different nibs, got %s twice" % (tuple(a),))
    if b.width > a.width:
        return NibAxis("NIBW", "Nib width", a.width, b.width, a, b)
    return NibAxis("NIBP", "Nib position", 0.0, 100.0, a, b)


def axis_masters(axis, budget):
    """User values of the masters along ``axis``: both ends, and intermediate ones
    halving each interval whose blend error (:func:`interpolation_error` of its end
    nibs) exceeds ``budget`` font units.

    Raises:
        MorphError: more than :data:`MAX_MASTERS` would be needed.
    """
    us = [0.0, 1.0]
    k = 0
    while k < len(us) - 1:
        a, b = (blend_nib(axis.nib_min, axis.nib_max, u) for u in us[k:k + 2])
        if interpolation_error(a, b) > budget:
            us.insert(k + 1, 0.5 * (us[k] + us[k + 1]))
            if len(us) > MAX_MASTERS:
                raise MorphError("the nib axis from %s to %s needs more than %d masters to "
                                 "stay within %g units: use nibs closer in angle and aspect"
                                 % (tuple(axis.nib_min), tuple(axis.nib_max), MAX_MASTERS,
                                    budget))
        else:
            k += 1
    return [axis.value(u) for u in us]


def variable_outputs(out_path):
    """(designspace path, masters folder) written next to a variable font."""
    out_path = Path(out_path)
    return (out_path.with_suffix(".designspace"),
            out_path.with_name(out_path.stem + "-masters"))


# ---------------------------------------------------------------- glyph jobs

def _keep_component(component):
    """A component kept as a component: a translation, or a half turn (an ellipse is
    centrally symmetric, so the stroke commutes with both)."""
    from .stroke import keep_component

    return keep_component(component, True)


def _glyph_job(args):
    """(name, loops per fitted master as lists of (k, 4, 2) arrays, CPU seconds) of
    one glyph: its paths in every skeleton master stroked by the nib of every fitted
    master (``owners``: its skeleton master), a process-pool job."""
    name, paths_by_master, nibs, owners, tol = args
    t0 = time.process_time()
    if not paths_by_master[0]:
        return name, [[] for _ in nibs], 0.0
    loops = fit_elements(skeleton_elements(paths_by_master, "glyph %r" % name), nibs, owners,
                         tol)
    return name, loops, time.process_time() - t0


def _plan(font, chosen):
    """(glyphs stroked, composites that follow) for an elliptical nib
    (:func:`morph.fonts.stroke.plan_components`)."""
    from .stroke import plan_components

    return plan_components(font, chosen, True)


def _work(fonts, stroked, nibs, owners, tol):
    from ..parse.ufo import component_paths, glyph_paths

    for n in stroked:
        per = []
        for font in fonts:
            g = font[n]
            paths = glyph_paths(g)
            for c in g.components:
                if not _keep_component(c):
                    paths.extend(component_paths(font, c))
            per.append(paths)
        yield n, per, nibs, owners, tol


# ------------------------------------------------------------------- masters

def _draw(glyph, loops, shift):
    pen = glyph.getPen()
    for loop in loops:
        pts = loop + np.array([shift, 0.0])
        pen.moveTo(_pt(pts[0, 0]))
        for c in pts:
            pen.curveTo(_pt(c[1]), _pt(c[2]), _pt(c[3]))
        pen.closePath()


def _pt(p):
    return (round(float(p[0]), 4), round(float(p[1]), 4))


def _master(font, results, nib, done, family, style):
    """A copy of the skeleton with the stroked outlines of one master drawn in."""
    m = copy.deepcopy(font)
    hx = float(nib.extent()[2])
    grow = int(round(2 * hx))
    shifts = {n: hx - (grow if m[n].width == 0 else 0) for n in done}
    for name, loops in results.items():
        g = m[name]
        g.clearContours()
        _draw(g, loops, shifts[name])
        g.lib[OVERLAP_KEY] = True
    for n in done:
        g = m[n]
        s = shifts[n]
        kept = []
        for c in g.components:
            if _keep_component(c):
                xx, xy, yx, yy, dx, dy = tuple(c.transformation)
                sb = shifts[c.baseGlyph]
                c.transformation = (xx, xy, yx, yy, dx + s - xx * sb, dy - xy * sb)
                kept.append(c)
        g.components[:] = kept
        if len(kept) > 1 or (kept and g.contours):
            g.lib[OVERLAP_KEY] = True
        for a in g.anchors:
            a.x += s
        for gl in g.guidelines:
            if gl.x is not None and gl.y is None:
                gl.x += s
        if g.width:
            g.width += grow
    for g in m:                 # an open skeleton cannot be compiled: left empty
        if g.name not in done and (g.contours or g.components):
            g.clearContours()
            g.clearComponents()
    info = m.info
    info.familyName = family
    info.styleName = style
    for key in ("styleMapFamilyName", "styleMapStyleName", "openTypeNamePreferredFamilyName",
                "openTypeNamePreferredSubfamilyName", "postscriptFontName",
                "postscriptFullName", "openTypeNameUniqueID", "postscriptUniqueID",
                "openTypeNameCompatibleFullName", "macintoshFONDName",
                "openTypeNameWWSFamilyName", "openTypeNameWWSSubfamilyName",
                "postscriptBlueValues", "postscriptOtherBlues", "postscriptFamilyBlues",
                "postscriptFamilyOtherBlues", "postscriptStemSnapH", "postscriptStemSnapV"):
        setattr(info, key, None)
    return m, shifts


def _grow_win(masters):
    """OS/2 win ascent / descent of every master grown to cover all masters' outlines
    (no clipping at any instance: the control points bound the curves)."""
    lo, hi = 0.0, 0.0
    for m in masters:
        for g in m:
            for c in g.contours:
                ys = [p.y for p in c.points]
                lo, hi = min(lo, min(ys)), max(hi, max(ys))
    for m in masters:
        info = m.info
        if info.openTypeOS2WinAscent is not None:
            info.openTypeOS2WinAscent = max(info.openTypeOS2WinAscent, int(np.ceil(hi)))
        if info.openTypeOS2WinDescent is not None:
            info.openTypeOS2WinDescent = max(info.openTypeOS2WinDescent, int(np.ceil(-lo)))


def _style(axis, value):
    return "%s %g" % (axis.name.split()[0], round(value, 2))


def _nib_axis_descriptor(axis):
    from fontTools.designspaceLib import AxisDescriptor, AxisLabelDescriptor

    ax = AxisDescriptor()
    ax.tag, ax.name = axis.tag, axis.name
    ax.minimum, ax.default, ax.maximum = axis.minimum, axis.minimum, axis.maximum
    ax.labelNames = {"en": axis.name}
    ax.axisLabels = [AxisLabelDescriptor(name=_axis_label(axis, v), userValue=v,
                                         elidable=(v == axis.minimum))
                     for v in _nib_instances(axis)]
    return ax


def _nib_instances(axis):
    """User values of the nib axis' named instances (and STAT labels): the ends and
    the middle."""
    return [axis.minimum, axis.value(0.5), axis.maximum]


def _axis_label(axis, v):
    """The STAT label and instance style of a nib axis value: "Regular" at the
    default (fontbakery wants a Regular instance at the default location)."""
    return "Regular" if v == axis.minimum else _style(axis, v)


def _designspace(skel, axis, fitted, masters, names, family):
    """The output designspace: the skeleton's axes (and instances, at the nib
    axis' default) plus the nib axis (and its instances at the skeleton's default)."""
    from fontTools.designspaceLib import DesignSpaceDocument, InstanceDescriptor, \
        SourceDescriptor

    doc = DesignSpaceDocument()
    for ax in skel.axes:
        doc.addAxis(_labelled(copy.deepcopy(ax), skel))
    if axis is not None:
        doc.addAxis(_nib_axis_descriptor(axis))
    for m, (s, v), fn in zip(masters, fitted, names):
        src = SourceDescriptor()
        src.filename, src.font = fn, m
        src.familyName, src.styleName = family, m.info.styleName
        src.location = dict(skel.locations[s])
        if axis is not None:
            src.location[axis.name] = v
        doc.addSource(src)
    seen = set()
    extra = {} if axis is None else {axis.name: axis.minimum}
    for inst in skel.instances:
        new = InstanceDescriptor()
        new.familyName = family
        new.styleName = inst.styleName or "Instance %d" % len(seen)
        new.location = {**dict(inst.location or {}), **extra}
        if (new.styleName not in seen):
            seen.add(new.styleName)
            doc.addInstance(new)
    if skel.axes and skel.default_style not in seen:     # a named default instance
        new = InstanceDescriptor()
        new.familyName, new.styleName = family, skel.default_style or "Regular"
        new.location = {**dict(skel.locations[skel.default]), **extra}
        seen.add(new.styleName)
        doc.addInstance(new)
    if axis is not None:
        base = dict(skel.locations[skel.default])
        for v in _nib_instances(axis):
            new = InstanceDescriptor()
            new.familyName = family
            label = _axis_label(axis, v)
            new.styleName = label if not skel.default_style or label != "Regular" else \
                skel.default_style
            if skel.default_style and label != "Regular":
                new.styleName = "%s %s" % (skel.default_style, label)
            new.location = {**base, axis.name: v}
            if new.styleName not in seen:
                seen.add(new.styleName)
                doc.addInstance(new)
    return doc


def _labelled(ax, skel):
    """A skeleton axis with STAT labels at its default ("Regular", elidable) and at
    every source and instance coordinate, unless it has labels already (the named
    instances need STAT values on every axis)."""
    from fontTools.designspaceLib import AxisLabelDescriptor

    if getattr(ax, "axisLabels", None):
        return ax
    default = skel.locations[skel.default]
    named = {}              # user value -> the style of a master or instance there
    places = [(loc, f.info.styleName) for loc, f in zip(skel.locations[:skel.given],
                                                         skel.fonts[:skel.given])]
    places += [(dict(i.location or {}), i.styleName) for i in skel.instances]
    for loc, style in places:
        if ax.name not in loc:
            continue
        u = round(float(ax.map_backward(loc[ax.name])), 3)
        alone = all(loc.get(k, v) == v for k, v in default.items() if k != ax.name)
        if alone and style and u != ax.default:
            named.setdefault(u, style)
        named.setdefault(u, "%s %g" % (ax.tag, u))
    named[ax.default] = "Regular"
    ax.axisLabels = [AxisLabelDescriptor(name=name, userValue=u, elidable=(u == ax.default))
                     for u, name in sorted(named.items())]
    return ax


@dataclass
class Skeleton:
    """Skeleton masters: ``fonts`` (ufoLib2), their design ``locations`` (axis name
    -> value), the designspace ``axes`` and ``instances`` (none for one UFO), the
    ``default`` master's index, ``labels`` (file names, for messages), ``given``:
    how many of the masters the designspace has (None: all; the others are
    intermediate ones, :mod:`morph.fonts.variable_skeleton`)."""

    fonts: list
    locations: list
    axes: list
    instances: list
    default: int
    labels: list
    given: int = None

    @property
    def default_style(self):
        return "" if not self.axes else (self.fonts[self.default].info.styleName or "")


def read_skeleton(src):
    """A :class:`Skeleton` from a UFO (path or ufoLib2 font) or a ``.designspace``.

    Raises:
        ParseError: unreadable designspace or UFO, a discrete axis, a source layer,
            no default source.
    """
    import ufoLib2

    from ..parse.ufo import load_ufo

    if isinstance(src, Skeleton):
        return src
    if isinstance(src, ufoLib2.Font):
        return Skeleton([src], [{}], [], [], 0, ["the UFO"])
    path = Path(src)
    if path.suffix.lower() != ".designspace":
        return Skeleton([load_ufo(path, lazy=False)], [{}], [], [], 0, [path.name])
    from fontTools.designspaceLib import DesignSpaceDocument

    try:
        doc = DesignSpaceDocument.fromfile(str(path))
    except Exception as exc:
        raise ParseError("cannot read designspace %s: %s" % (path, one_line(exc)),
                         str(path)) from exc
    if any(not hasattr(ax, "minimum") for ax in doc.axes):
        raise ParseError("designspace %s has a discrete axis: only continuous axes are "
                         "supported" % path, str(path))
    if not doc.sources:
        raise ParseError("designspace %s has no sources" % path, str(path))
    default = doc.findDefault()
    if default is None:
        raise ParseError("designspace %s has no source at the axes' defaults" % path,
                         str(path))
    fonts, locations, labels = [], [], []
    for s in doc.sources:
        if s.layerName:
            raise ParseError("designspace %s: source %s is a layer (%s); sparse layer "
                             "masters are not supported" % (path, s.filename, s.layerName),
                             str(path))
        fonts.append(load_ufo(s.path, lazy=False))
        locations.append(dict(s.location))
        labels.append(s.filename or Path(s.path).name)
    return Skeleton(fonts, locations, list(doc.axes), list(doc.instances),
                    doc.sources.index(default), labels)


def _check_glyphs(skel, names):
    """Every stroked glyph in every master, with the same kept components."""
    from ..compatible import IncompatibleMasters

    base = skel.fonts[skel.default]
    for n in names:
        want = [(c.baseGlyph, _keep_component(c)) for c in base[n].components]
        for font, label in zip(skel.fonts, skel.labels):
            if n not in font:
                raise IncompatibleMasters("glyph %r is missing from master %s" % (n, label),
                                          "glyph")
            got = [(c.baseGlyph, _keep_component(c)) for c in font[n].components]
            if got != want:
                raise IncompatibleMasters("glyph %r: its components differ between masters "
                                          "%s and %s" % (n, skel.labels[skel.default], label),
                                          "components")


def set_overlap_flags(ttfont):
    """Set OVERLAP_SIMPLE on every simple glyph with contours and OVERLAP_COMPOUND on
    every composite of a glyf font (no-op for CFF2); returns how many were set."""
    from fontTools.ttLib.tables._g_l_y_f import OVERLAP_COMPOUND, flagOverlapSimple

    if "glyf" not in ttfont:
        return 0
    count = 0
    glyf = ttfont["glyf"]
    for name in glyf.keys():
        g = glyf[name]
        if g.isComposite():
            g.components[0].flags |= OVERLAP_COMPOUND
            count += 1
        elif g.numberOfContours > 0:
            g.flags[0] |= flagOverlapSimple
            count += 1
    return count


def _compile(doc, kind, cu2qu_error_em):
    """The designspace compiled by ufo2ft, its variation models given the grid's tents
    (:class:`morph.fonts.variable_grid.grid_supports`: the masters, a product grid,
    reproduced exactly by integer deltas); a CFF2 charstring longer than a reader
    takes split into subroutines (:func:`morph.fonts.variable_cff2.split_long_charstrings`)."""
    import ufo2ft

    from .variable_cff2 import split_long_charstrings
    from .variable_grid import grid_supports

    try:
        with grid_supports():
            if kind == ".otf":
                font = ufo2ft.compileVariableCFF2(doc, optimizeCFF=False)
            else:
                return ufo2ft.compileVariableTTF(doc, cubicConversionError=cu2qu_error_em,
                                                 optimizeGvar=False)
    except Exception as exc:
        raise MorphError("ufo2ft could not compile the variable font: %s"
                         % one_line(exc)) from exc
    split_long_charstrings(font)
    return font


def stroke_variable(src, out_path, nib_min, nib_max=None, glyphs=None, tol=0.5,
                    family_name=None, overwrite=False, jobs=1, progress=None):
    """Write a variable calligraphic font from a skeleton UFO or designspace.

    ``src``: a skeleton ``.ufo`` or ``.designspace`` (or an open ``ufoLib2.Font``,
    not modified); ``out_path``: ``.ttf`` (glyf/gvar) or ``.otf`` (CFF2), with the
    designspace and master UFOs beside it (:func:`variable_outputs`); ``nib_min``:
    (width, height, angle) of the nib, and with ``nib_max`` the nib axis from one
    to the other (every skeleton master is stroked at every nib master); a
    designspace keeps its axes and instances.  ``glyphs``: characters or names
    (None: all); ``tol``: font units, split as the module docstring says;
    ``family_name``: default "FAMILY Nib" with a nib axis, else "FAMILY Stroke"
    (short: fontbakery wants family and style names within 31 characters);
    ``overwrite``: replace existing outputs (the masters folder is replaced whole);
    ``jobs``: processes; ``progress(name)`` after each glyph.

    Returns a dict: ``axis`` (:class:`NibAxis` or None), ``values`` (the nib
    masters' user values), ``designspace``, ``masters`` (paths), ``glyphs``,
    ``followed``, ``points`` (per master), ``fit_seconds`` (CPU, all glyphs and
    masters), ``seconds`` (wall), ``font`` (the compiled TTFont), ``sources`` (the
    master ufoLib2 fonts), ``fitted`` ((skeleton master, nib value) per master).

    Raises:
        ParseError: unreadable sources or glyphs; IncompatibleMasters: skeleton
            masters that differ (the message names the glyph and what differs);
        MorphError: outputs exist without ``overwrite``, ufo2ft fails; ValueError:
            a bad suffix, tol <= 0, equal nibs.
    """
    from ..parse.ufo import glyph_names_for

    t_start = time.perf_counter()
    out_path = Path(out_path)
    kind = out_path.suffix.lower()
    ds_path, masters_dir = _check_outputs(out_path, tol, overwrite)
    skel = read_skeleton(src)
    font = skel.fonts[skel.default]
    chosen = list(font.keys()) if glyphs is None else glyph_names_for(font, glyphs)
    stroked, followed = _plan(font, chosen)
    skel, axis, values, fitted, nibs, refined, results = _stroke_masters(
        skel, stroked, followed, nib_min, nib_max, tol, jobs, progress)
    fit_seconds = sum(r[2] for r in results)
    family = family_name or "%s %s" % (font.info.familyName or "Morph",
                                        "Nib" if axis is not None else "Stroke")
    masters, names = _masters_of(skel, axis, fitted, nibs, results,
                                 set(stroked) | set(followed), family, out_path, masters_dir)
    doc = _designspace(skel, axis, fitted, masters, names, family)
    upm = float(font.info.unitsPerEm or 1000)
    vf = _compile(doc, kind, CU2QU_SHARE * tol / upm)
    set_overlap_flags(vf)
    _write(out_path, vf, doc, masters, names, ds_path, masters_dir)
    points = sum(len(c) for g in masters[0] for c in g.contours)
    return {"axis": axis, "values": values if axis else [], "designspace": ds_path,
            "masters": [ds_path.parent / n for n in names], "glyphs": len(stroked),
            "followed": len(followed), "points": points, "fit_seconds": fit_seconds,
            "seconds": time.perf_counter() - t_start, "font": vf, "sources": masters,
            "fitted": fitted, "skeleton": refined}


def _stroke_masters(skel, stroked, followed, nib_min, nib_max, tol, jobs, progress):
    """The masters chosen (:func:`_fitted_masters`) and every stroked glyph fitted at
    all of them (run_jobs of :func:`_glyph_job`): (skeleton with its intermediate
    masters, axis, nib values, fitted, nibs, skeleton report, results).

    Raises:
        IncompatibleMasters: naming the glyph, what differs and the master's file."""
    from ..compatible import IncompatibleMasters
    from .jobs import run_jobs

    try:
        _check_glyphs(skel, stroked + followed)
        skel, axis, values, fitted, nibs, refined = _fitted_masters(skel, nib_min, nib_max,
                                                                     tol, stroked, followed)
        owners = [s for s, _ in fitted]
        report = None if progress is None else (lambda k, r: progress(r[0]))
        results = run_jobs(_glyph_job, list(_work(skel.fonts, stroked, nibs, owners,
                                                  FIT_SHARE * tol)),
                           jobs=jobs, progress=report)
    except IncompatibleMasters as exc:
        raise IncompatibleMasters(_name_masters(str(exc), skel.labels), exc.what) from None
    return skel, axis, values, fitted, nibs, refined, results


def _fitted_masters(skel, nib_min, nib_max, tol, stroked, followed=()):
    """(skeleton with its intermediate masters, axis or None, the nib axis's master
    values, (skeleton master, nib value) per fitted master, the nib of each, the
    skeleton refinement's report): every skeleton master at every nib master, as
    many of each as keep an instance within BLEND_SHARE of tol (split in halves
    when both the nib axis and the skeleton's interpolation are inexact)."""
    from .variable_skeleton import refine_skeleton

    if nib_max is None and len(skel.fonts) < 2:
        raise ValueError("a variable font needs a nib axis or several skeleton masters")
    axis = None if nib_max is None else nib_axis(nib_min, nib_max)
    both = axis is not None and len(skel.fonts) > 1 and \
        interpolation_error(axis.nib_min, axis.nib_max) > 1e-9 * axis.nib_max.width
    share = BLEND_SHARE * tol / (2.0 if both else 1.0)
    values = [None] if axis is None else axis_masters(axis, share)
    nibs_v = [Ellipse(*map(float, nib_min))] if axis is None else \
        [axis.nib_at(v) for v in values]
    ends = [nibs_v[0], nibs_v[-1]]
    skel, refined = refine_skeleton(skel, stroked, ends, share, _keep_component, followed)
    fitted = [(s, v) for s in range(len(skel.fonts)) for v in values]
    return skel, axis, values, fitted, [nibs_v[values.index(v)] for _, v in fitted], refined


def _check_outputs(out_path, tol, overwrite):
    """(designspace path, masters folder) of a variable font written to ``out_path``,
    after checking the suffix, ``tol`` and that nothing is overwritten unasked."""
    if out_path.suffix.lower() not in (".ttf", ".otf"):
        raise ValueError("a variable font is a .ttf or .otf, got %s" % out_path)
    if not tol > 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    ds_path, masters_dir = variable_outputs(out_path)
    for p in (out_path, ds_path, masters_dir):
        if p.exists() and not overwrite:
            raise MorphError("%s exists (pass overwrite=True to replace it)" % p)
    return ds_path, masters_dir


def _masters_of(skel, axis, fitted, nibs, results, done, family, out_path, masters_dir):
    """(master ufoLib2 fonts, their file names relative to the designspace): one per
    (skeleton master, nib value) of ``fitted``, styled by both, win metrics shared."""
    masters, names, offsets = [], [], []
    for k, ((s, v), nib) in enumerate(zip(fitted, nibs)):
        per = {name: loops[k] for name, loops, _ in results}
        parts = [(skel.fonts[s].info.styleName or "") if skel.axes else "",
                 _axis_label(axis, v) if axis else ""]
        if parts[0] and parts[1] == "Regular":
            parts[1] = ""
        style = " ".join(x for x in parts if x)
        m, shifts = _master(skel.fonts[s], per, nib, done, family, style or "Regular")
        masters.append(m)
        offsets.append(shifts)
        names.append("%s/%s-%s.ufo" % (masters_dir.name, out_path.stem,
                                       _file_part(style or "Regular")))
    if len(set(names)) < len(names):
        names = ["%s/%s-%d.ufo" % (masters_dir.name, out_path.stem, k)
                 for k in range(len(names))]
    _grow_win(masters)
    _vary_features(skel, axis, fitted, masters, offsets)
    return masters, names


def _vary_features(skel, axis, fitted, masters, offsets):
    """The explicit anchors of the skeleton masters' feature files (ufo2ft compiles
    the default's) moved like their glyphs at every master and given each master's
    own values: variable anchors where they differ between masters
    (:func:`morph.fonts.fea.vary_feature_anchors`), written into every master.  The
    intermediate skeleton masters are left to the variable anchors' own
    interpolation over the designspace's masters (the skeleton's, as theirs are)."""
    from .fea import vary_feature_anchors

    text = skel.fonts[skel.default].features.text or ""
    if "anchor" not in text:
        return
    given = skel.given or len(skel.fonts)
    per = []
    for (s, v), shifts in zip(fitted, offsets):
        if s >= given:
            continue
        loc = {ax.tag: float(ax.map_backward(skel.locations[s].get(
            ax.name, ax.map_forward(ax.default)))) for ax in skel.axes}
        if axis is not None:
            loc[axis.tag] = v
        own = None if s == skel.default else (skel.fonts[s].features.text or "")
        per.append((loc, lambda g, sh=shifts: (sh[g], 0.0) if g in sh else None, own))
    new = vary_feature_anchors(text, masters[0].keys(), per)
    for m in masters:
        m.features.text = new


def _file_part(style):
    import re

    return re.sub(r"[^A-Za-z0-9]+", "", style.replace(".", "_").replace(" ", "")) or "Master"


def _name_masters(message, labels):
    """'master 1' in a compatibility message -> the master's file name."""
    import re

    return re.sub(r"master (\d+)", lambda m: "master %s" % labels[int(m.group(1))], message)


def _write(out_path, vf, doc, masters, names, ds_path, masters_dir):
    """Font, designspace and masters written to a temporary folder, then moved into
    place (an existing masters folder is replaced whole: nothing stale is left)."""
    parent = out_path.parent
    parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".morph-variable-", dir=str(parent)))
    try:
        vf.save(str(tmp / out_path.name))
        (tmp / masters_dir.name).mkdir()
        for m, n in zip(masters, names):
            m.save(str(tmp / n), overwrite=True)
        for s in doc.sources:       # the document refers to the files, not the objects
            s.font = None
        doc.write(str(tmp / ds_path.name))
        if masters_dir.exists():
            shutil.rmtree(masters_dir)
        os.replace(str(tmp / masters_dir.name), str(masters_dir))
        os.replace(str(tmp / ds_path.name), str(ds_path))
        os.replace(str(tmp / out_path.name), str(out_path))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
